// The binary's heading paths: `--sentences HDT,THS` on a simulated circle gives the heading of
// the car (its direction of travel, counter-clockwise from east) with --heading-noise 0; a fleet
// file with a moving base and a rover starts, the base's output carries RTCM3 that gpsdecode
// reads, the rover's carries NAV-RELPOSNED once a client turns it on (here: not valid, nobody
// forwards the corrections in a --fast run).
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "emulator/rtk/rtcm3_reader.hpp"
#include "nmea/heading.hpp"
#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace heading_test {

TEST(HeadingE2e, HdtAndThsFollowTheSimulatedCircle) {
  // radius 20 m at 2 m/s: 0.1 rad/s, so epoch k (1 Hz) faces 90 - 5.7296 k degrees
  const auto r = test::run_fast(GPSEMU_BINARY, {"--source", "sim:circle", "--duration", "5", "--sentences",
                                                "GGA,HDT,THS", "--heading-noise", "0", "--talker", "GN"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  int k = 0, ths = 0;
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto s = nmea::parse_sentence(line);
    ASSERT_TRUE(s) << line;
    if (s->type == "HDT") {
      const auto h = nmea::parse_hdt(*s);
      ASSERT_TRUE(h && h->heading_deg_true) << line;
      const double expected = std::fmod(90.0 - k * 0.1 * 180.0 / M_PI + 360.0, 360.0);
      EXPECT_NEAR(*h->heading_deg_true, expected, 0.006) << line;
      ++k;
    } else if (s->type == "THS") {
      const auto h = nmea::parse_ths(*s);
      ASSERT_TRUE(h) << line;
      EXPECT_EQ(h->mode, 'A') << line;
      ++ths;
    }
  }
  EXPECT_EQ(k, 5);
  EXPECT_EQ(ths, 5);
}

TEST(HeadingE2e, MovingBaseFleetWritesRtcm3) {
  const auto dir = test::scratch_dir("heading", "fleet");
  const auto base = dir / "base.bin", rover = dir / "rover.bin";
  const auto config = test::write_file(dir / "pair.toml",
                                       "source = \"sim:circle\"\n"
                                       "protocol = \"ubx\"\n"
                                       "[[receiver]]\n"
                                       "receiver = \"ublox-f9p\"\n"  // (at the top level it would clash with [[receiver]])
                                       "role = \"moving-base\"\n"
                                       "antenna-offset = \"-0.5,0,0\"\n"
                                       "output = \"file:" + base.string() + "\"\n"
                                       "[[receiver]]\n"
                                       "receiver = \"ublox-f9p\"\n"
                                       "role = \"rover\"\n"
                                       "antenna-offset = \"0.5,0,0\"\n"
                                       "output = \"file:" + rover.string() + "\"\n");
  const auto r = test::run({GPSEMU_BINARY, "--config", config.string(), "--fast", "--duration", "3", "--log-level",
                            "warn", "--start-time", "2024-05-01T00:00:00Z"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto decoded = test::run({"/bin/sh", "-c", "gpsdecode -j < '" + base.string() + "'"});
  ASSERT_EQ(decoded.status, 0) << decoded.err;
  int rtcm = 0, bias = 0;
  std::istringstream lines(decoded.out);
  for (std::string line; std::getline(lines, line);) {
    if (test::contains(line, "\"class\":\"RTCM3\"")) ++rtcm;
    if (test::contains(line, "\"type\":1230")) ++bias;
  }
  EXPECT_EQ(bias, 3);
  EXPECT_GE(rtcm, 3 * 3);  // 4072.0, at least one MSM4 and 1230 an epoch
  rtk::Rtcm3Reader rover_frames;
  (void)rover_frames.feed(test::read_file(rover));
  EXPECT_EQ(rover_frames.stats().frames_ok, 0u);  // the rover writes no RTCM3
  EXPECT_FALSE(test::read_file(rover).empty());
}

TEST(HeadingE2e, ARoverWithoutABaseIsRefused) {
  const auto r = test::run_fast(GPSEMU_BINARY, {"--role", "rover", "--protocol", "ubx", "--antenna-offset", "1,0,0"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(test::contains(r.err, "needs a receiver with role = \"moving-base\"")) << r.err;
}

}  // namespace heading_test
}  // namespace
}  // namespace gpsemu
