// The control socket's protocol: live faults start at the next epoch, clear ends them there,
// status reports each receiver; every bad line is an ERROR object, never an exception.
#include "emulator/faults/control.hpp"

#include <gtest/gtest.h>

#include "tests/support/fault_fixes.hpp"

#include <chrono>

#include <nlohmann/json.hpp>

namespace gpsemu::faults {
namespace {
namespace control_test {

using nlohmann::json;
using std::chrono::milliseconds;

const UtcNs kStart = UtcNs{std::chrono::duration_cast<UtcNs::duration>(std::chrono::hours(24 * 20000))};

struct TwoReceivers {
  TwoReceivers() : frame({47.0, 8.0, 400.0}), a({{}, ""}, kStart), b({{}, ""}, kStart), control({&a, &b}) {}
  /// Epoch `ms` after the start for both receivers: a fix of 8 satellites at the origin.
  void epoch(int ms, nmea::Fix* out_a = nullptr) {
    for (FaultTimeline* t : {&a, &b}) {
      nmea::Fix fix;
      fix.quality = nmea::FixQuality::gps;
      fix.satellites_in_view = 8;
      for (int i = 0; i < 8; ++i) {
        fix.satellites[static_cast<std::size_t>(i)].used = true;
        fix.satellites[static_cast<std::size_t>(i)].snr_dbhz = 40;
      }
      fix.satellites_used = 8;
      (void)test::apply_faults(*t, kStart + milliseconds(ms), fix, Enu{}, frame);
      if (t == &a && out_a) *out_a = fix;
    }
  }
  json ask(const std::string& line) { return json::parse(control.handle(line)); }
  LocalFrame frame;
  FaultTimeline a, b;
  FaultControl control;
};

TEST(FaultControl, AFaultStartsAtTheNextEpochOfItsReceiverAndClearEndsIt) {
  TwoReceivers r;
  r.epoch(0);
  const json answer = r.ask(R"({"fault":"jam","db":30,"receiver":0})");
  EXPECT_EQ(answer["class"], "FAULT");
  EXPECT_EQ(answer["receivers"], json::array({0}));
  nmea::Fix fix;
  r.epoch(100, &fix);
  EXPECT_FALSE(fix.has_fix());  // 40 - 30 dB-Hz: under the tracking threshold
  ASSERT_EQ(r.a.entries().size(), 1u);
  EXPECT_DOUBLE_EQ(r.a.entries()[0].fault.at_s, 0.1);
  EXPECT_TRUE(r.b.entries().empty());
  const json status = r.ask(R"({"status":true})");
  EXPECT_EQ(status["class"], "STATUS");
  EXPECT_EQ(status["receivers"][0]["faults"][0]["fault"], "jam");
  EXPECT_EQ(status["receivers"][0]["quality"], 0);
  EXPECT_EQ(status["receivers"][1]["quality"], 1);
  EXPECT_EQ(status["receivers"][1]["epochs"], 2);
  const json cleared = r.ask(R"({"clear":"jam"})");
  EXPECT_EQ(cleared["class"], "CLEAR");
  EXPECT_EQ(cleared["cleared"], 1);
  r.epoch(200, &fix);
  EXPECT_TRUE(fix.has_fix());
  EXPECT_EQ(r.a.entries()[0].epochs, 1u);
  EXPECT_TRUE(r.ask(R"({"status":true})")["receivers"][0]["faults"].empty());
}

TEST(FaultControl, ALiveFaultWithADurationEndsByItself) {
  TwoReceivers r;
  r.epoch(0);
  (void)r.ask(R"({"fault":"outage","duration":0.2})");
  nmea::Fix fix;
  r.epoch(100, &fix);
  EXPECT_FALSE(fix.has_fix());
  r.epoch(200, &fix);
  EXPECT_FALSE(fix.has_fix());
  r.epoch(300, &fix);
  EXPECT_TRUE(fix.has_fix());
  EXPECT_EQ(r.b.entries().size(), 1u);  // "receiver" absent: every receiver
}

TEST(FaultControl, EveryBadLineIsAnErrorObject) {
  TwoReceivers r;
  for (const char* line : {"", "nope", "[1,2]", "{}", R"({"fault":"meteor"})", R"({"fault":"jam"})",
                           R"({"fault":"jam","db":25,"at":3})", R"({"fault":"jam","db":25,"receiver":2})",
                           R"({"fault":"jam","db":25,"receiver":-1})", R"({"fault":"jam","db":[1]})",
                           R"({"clear":"meteor"})", R"({"clear":3})", "{\"fault\":\"jam\",\"db\":1e999}",
                           "{\"fault\":\"\xff\"}"}) {
    const json answer = json::parse(r.control.handle(line), nullptr, false);
    ASSERT_FALSE(answer.is_discarded()) << line;
    EXPECT_EQ(answer["class"], "ERROR") << line;
    EXPECT_FALSE(answer["message"].get<std::string>().empty()) << line;
  }
  EXPECT_EQ(r.ask(R"({"fault":"jam","db":25,"receiver":2})")["message"], "receiver: expected an index 0..1 or \"all\", got 2");
  EXPECT_TRUE(r.a.entries().empty());
}

TEST(FaultControl, AnswersNameTheEpochTheyCameAfterAndEachReceiverRecordsTheEventItApplied) {
  TwoReceivers r;
  EXPECT_TRUE(r.ask(R"({"fault":"outage"})")["after_epoch_s"].is_null());  // before the first epoch
  r.epoch(0);
  r.epoch(100);
  const json answer = r.ask(R"({"fault":"garble","rate":0.5,"unused":[1]})");
  EXPECT_EQ(answer["class"], "ERROR");  // a fault's keys are its parameters: an array is refused
  const json ok = r.ask(R"({"fault":"latency","delay_ms":300})");
  EXPECT_DOUBLE_EQ(ok["after_epoch_s"].get<double>(), 0.1);
  r.epoch(200);
  ASSERT_EQ(r.a.applied_events().size(), 1u);  // the outage applied at epoch 0 was that epoch's
  EXPECT_EQ(r.a.applied_events()[0].request, R"({"delay_ms":300,"fault":"latency","receiver":0})");
  EXPECT_EQ(r.b.applied_events()[0].request, R"({"delay_ms":300,"fault":"latency","receiver":1})");
  EXPECT_DOUBLE_EQ(r.a.applied_events()[0].since_s, 0.2);
  EXPECT_EQ(r.ask(R"({"fault":"outage","at_utc":"2026-01-01T00:00:00Z"})")["class"], "ERROR");
  EXPECT_EQ(r.ask(R"({"fault":"jam","db":20,"where":"circle:47,8,100","ramp_out_s":2})")["class"], "FAULT");
}

TEST(FaultControl, StatusShowsAnAcceptedFaultAsPendingBeforeTheNextEpoch) {
  TwoReceivers r;
  r.epoch(0);
  ASSERT_EQ(r.ask(R"({"fault":"jam","db":30,"receiver":0})")["class"], "FAULT");
  const json before = r.ask(R"({"status":true})");
  ASSERT_EQ(before["receivers"][0]["faults"].size(), 1u) << before.dump();
  const json& pending = before["receivers"][0]["faults"][0];
  EXPECT_EQ(pending["fault"], "jam");
  EXPECT_EQ(pending["pending"], true);
  EXPECT_EQ(pending["starts"], "next epoch");
  EXPECT_EQ(pending["active"], false);
  EXPECT_EQ(pending["describe"], "jam db=30 until cleared");
  EXPECT_TRUE(before["receivers"][1]["faults"].empty());
  r.epoch(100);
  const json after = r.ask(R"({"status":true})");
  EXPECT_EQ(after["receivers"][0]["faults"][0]["active"], true);
  EXPECT_FALSE(after["receivers"][0]["faults"][0].contains("pending"));
  (void)r.ask(R"({"clear":"jam"})");
  EXPECT_EQ(r.ask(R"({"status":true})")["receivers"][0]["faults"][0]["ends"], "next epoch");
}

TEST(FaultControl, AClearedLiveFaultIsSummarisedUntilItsClearNotToTheEnd) {
  TwoReceivers r;
  r.epoch(0);
  (void)r.ask(R"({"fault":"jam","db":30,"receiver":0})");
  r.epoch(1000);
  r.epoch(2000);
  (void)r.ask(R"({"clear":"jam"})");
  r.epoch(3000);
  r.epoch(4000);
  const std::vector<std::string> lines = r.a.summary_lines();
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "fault jam db=30 at 1 s for 2 s (cleared): 2 epochs");
}

TEST(FaultControl, ASecondSpoofOnAReceiverWithOneOnIsRefused) {
  TwoReceivers r;
  r.epoch(0);
  ASSERT_EQ(r.ask(R"({"fault":"spoof","speed_mps":2,"receiver":0})")["class"], "FAULT");
  const json pending = r.ask(R"({"fault":"spoof","speed_mps":2})");  // before the first one started
  EXPECT_EQ(pending["class"], "ERROR");
  EXPECT_EQ(pending["message"], "spoof: receiver 0 has a spoof on (spoof speed_mps=2 bearing_deg=0 undetected until cleared): "
                                "two spoofers would add their drags; clear spoof first");
  r.epoch(100);
  EXPECT_EQ(r.ask(R"({"fault":"spoof","speed_mps":1,"receiver":0})")["class"], "ERROR");
  EXPECT_EQ(r.ask(R"({"fault":"spoof","speed_mps":1,"receiver":1})")["class"], "FAULT");  // the other receiver has none
  (void)r.ask(R"({"clear":"spoof","receiver":0})");
  EXPECT_EQ(r.ask(R"({"fault":"spoof","speed_mps":1,"receiver":0})")["class"], "FAULT");  // after the clear
}

// A live spoof on a receiver whose scenario has a spoof to come would stack with it when that one
// starts (the two drags added, 95 m in the trial): refused, naming the scheduled one and the longest
// duration that ends before it; one that ends in time is accepted.
TEST(FaultControl, ALiveSpoofThatWouldOverlapAScheduledSpoofIsRefused) {
  Fault scheduled = make_fault({{"kind", std::string("spoof")}, {"at", 2.0}, {"duration", 3.0}, {"speed_mps", 5.0}});
  scheduled.origin = {"scenario file s.toml", 1, {}};
  FaultTimeline t({{scheduled}, ""}, kStart);
  FaultControl control({&t});
  const LocalFrame frame({47.0, 8.0, 400.0});
  nmea::Fix fix;
  (void)test::apply_faults(t, kStart + milliseconds(500), fix, Enu{}, frame);
  const json on = json::parse(control.handle(R"({"fault":"spoof","speed_mps":2})"));
  EXPECT_EQ(on["class"], "ERROR");
  EXPECT_EQ(on["message"], "spoof: receiver 0 has a spoof scheduled from 2 s (scenario file s.toml:1): two spoofers would add "
                           "their drags; give a duration under 1.5 s, or clear spoof first");
  const json fading = json::parse(control.handle(R"({"fault":"spoof","speed_mps":2,"duration":1,"ramp_out_s":1})"));
  EXPECT_EQ(fading["class"], "ERROR") << fading;  // its fade out would still be on at 2 s
  const json brief = json::parse(control.handle(R"({"fault":"spoof","speed_mps":2,"duration":1})"));
  EXPECT_EQ(brief["class"], "FAULT") << brief;
  // After the scheduled one ends, a spoof until cleared is fine.
  for (int ms = 1000; ms <= 5000; ms += 500) (void)test::apply_faults(t, kStart + milliseconds(ms), fix, Enu{}, frame);
  EXPECT_EQ(json::parse(control.handle(R"({"fault":"spoof","speed_mps":2})"))["class"], "FAULT");
}

// `clear spoof` then `spoof ...` before the next epoch (an operator changing the spoof's speed):
// the clear ends the old spoof only; the new one starts at the next epoch (it was ended unstarted,
// though the answer said it would start), and the --tee file records them in that order.
TEST(FaultControl, AFaultAskedForAfterAClearOfItsKindStartsAtTheNextEpoch) {
  TwoReceivers r;
  r.epoch(0);
  ASSERT_EQ(r.ask(R"({"fault":"spoof","speed_mps":2,"receiver":0})")["class"], "FAULT");
  r.epoch(100);
  ASSERT_EQ(r.ask(R"({"clear":"spoof","receiver":0})")["cleared"], 1);
  ASSERT_EQ(r.ask(R"({"fault":"spoof","speed_mps":4,"receiver":0})")["class"], "FAULT");
  r.epoch(200);
  ASSERT_EQ(r.a.entries().size(), 2u);
  EXPECT_TRUE(r.a.entries()[0].cleared);
  EXPECT_FALSE(r.a.entries()[1].ended);
  EXPECT_TRUE(r.a.entries()[1].active);
  EXPECT_DOUBLE_EQ(std::get<Spoof>(r.a.entries()[1].fault.params).speed_mps, 4.0);
  ASSERT_EQ(r.a.applied_events().size(), 2u);
  EXPECT_EQ(r.a.applied_events()[0].request, R"({"clear":"spoof","receiver":0})");
  EXPECT_EQ(r.a.applied_events()[1].request, R"({"fault":"spoof","receiver":0,"speed_mps":4})");
  const json status = r.ask(R"({"status":true})");
  EXPECT_EQ(status["receivers"][0]["faults"].size(), 1u) << status;
  EXPECT_EQ(status["receivers"][0]["faults"][0]["describe"], "spoof speed_mps=4 bearing_deg=0 undetected at 0.2 s to the end");
}

}  // namespace control_test
}  // namespace
}  // namespace gpsemu::faults
