// A live session's events in the --tee file and back: the line written, and the faults a tee
// file's lines give (a fault at its epoch, a clear ending it).
#include "emulator/faults/tee_events.hpp"

#include <gtest/gtest.h>

#include "tests/support/fault_fixes.hpp"

#include <stdexcept>

namespace gpsemu::faults {
namespace {
namespace tee_events_test {

const UtcNs kStart = parse_iso8601_utc("2024-05-01T00:00:00Z");

TEST(TeeEvents, TheLineHoldsTheSecondsTheEpochAndTheRequest) {
  const AppliedEvent e{kStart + std::chrono::milliseconds(12300), 12.3, R"({"db":25,"fault":"jam","receiver":0})"};
  EXPECT_EQ(tee_event_line(e), R"(# fault +12.300000000 2024-05-01T00:00:12.300Z {"db":25,"fault":"jam","receiver":0})");
}

TEST(TeeEvents, ATeeFileIsToldFromAToml) {
  EXPECT_TRUE(looks_like_tee("# sent 2024-05-01T00:00:00.000100Z\n$GPRMC,...\n"));
  EXPECT_TRUE(looks_like_tee("$GPGGA\r\n# fault +1.000000000 2024-05-01T00:00:01.000Z {}\n"));
  EXPECT_FALSE(looks_like_tee("# a scenario\n[[fault]]\nkind = \"outage\"\n"));
}

TEST(TeeEvents, FaultsStartAtTheirEpochAndClearsEndThem) {
  const std::string tee =
      "# sent 2024-05-01T00:00:00.000100Z\n$GPGGA,000000.00*00\r\n"
      "# fault +2.000000000 2024-05-01T00:00:02.000Z {\"db\":25,\"fault\":\"jam\",\"ramp_s\":5,\"receiver\":0}\n"
      "# sent 2024-05-01T00:00:02.000100Z\n$GPGGA,000002.00*00\r\n"
      "# fault +3.000000000 2024-05-01T00:00:03.000Z {\"duration\":1.5,\"fault\":\"outage\",\"receiver\":0}\n"
      "# fault +7.500000000 2024-05-01T00:00:07.500Z {\"clear\":\"jam\",\"receiver\":0}\n";
  const std::vector<Fault> faults = faults_from_tee(tee);
  ASSERT_EQ(faults.size(), 2u);
  EXPECT_EQ(faults[0].kind(), FaultKind::jam);
  EXPECT_EQ(faults[0].at_s, 2.0);
  EXPECT_EQ(std::get<Jam>(faults[0].params).db, 25.0);
  EXPECT_EQ(faults[0].ramp_s, 5.0);
  ASSERT_TRUE(faults[0].duration_s);
  EXPECT_DOUBLE_EQ(*faults[0].duration_s, 5.5);
  EXPECT_EQ(faults[0].receiver, 0);
  EXPECT_EQ(faults[1].kind(), FaultKind::outage);
  EXPECT_EQ(faults[1].at_s, 3.0);
  EXPECT_EQ(faults[1].duration_s, 1.5);  // over before the clear: untouched
}

TEST(TeeEvents, AClearDisarmsAnAreasFaultFromItsEpoch) {
  const std::vector<Fault> faults = faults_from_tee(
      "# fault +1.000000000 2024-05-01T00:00:01.000Z {\"fault\":\"outage\",\"receiver\":0,\"where\":\"circle:47,8,100\"}\n"
      "# fault +4.000000000 2024-05-01T00:00:04.000Z {\"clear\":\"all\",\"receiver\":0}\n");
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].at_s, 1.0);
  EXPECT_FALSE(faults[0].duration_s);  // each visit as long as it lasts
  EXPECT_EQ(faults[0].disarm_s, 4.0);
  // In a timeline: on inside from 1 s, never again from 4 s.
  const LocalFrame frame({47.0, 8.0, 0.0});
  FaultTimeline timeline({faults, ""}, kStart);
  std::vector<bool> fixes;
  for (int s = 0; s < 6; ++s) {
    nmea::Fix fix;
    fix.quality = nmea::FixQuality::gps;
    fix.satellites_in_view = fix.satellites_used = 8;
    (void)test::apply_faults(timeline, kStart + std::chrono::seconds(s), fix, Enu{}, frame);
    fixes.push_back(fix.has_fix());
  }
  EXPECT_EQ(fixes, (std::vector<bool>{true, false, false, false, true, true}));
  EXPECT_TRUE(timeline.entries()[0].ended);
}

TEST(TeeEvents, ABadLineIsNamed) {
  try {
    (void)faults_from_tee("# sent x\n# fault +1.0 2024-05-01T00:00:01.000Z {\"fault\":\"jam\"}\n");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "line 2: db: missing (jam lowers C/N0 by db dB; or leave = N: as far as leaves at most N "
              "satellites tracked, whatever the sky)");
  }
  EXPECT_THROW((void)faults_from_tee("# fault +x {}\n"), std::invalid_argument);
}

}  // namespace tee_events_test
}  // namespace
}  // namespace gpsemu::faults
