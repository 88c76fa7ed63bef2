// The triggers of a fault beside `at`: a UTC time (at_utc) and a place (where: the truth inside a
// circle or polygon); the ramp out (ramp_out_s); the byte-level faults' effect (garble, latency);
// live events recorded as they apply (for the --tee file).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "emulator/faults/fault_timeline.hpp"
#include "tests/support/fault_fixes.hpp"

namespace gpsemu::faults {
namespace {
namespace fault_triggers_test {

using std::chrono::seconds;

const Geodetic kOrigin{47.0, 8.0, 400.0};
const UtcNs kStart = parse_iso8601_utc("2026-03-01T10:00:00Z");

/// A gps fix of 10 used satellites at `truth_m` (no error).
nmea::Fix make_fix(const LocalFrame& frame, UtcNs t, const Enu& truth_m) {
  nmea::Fix fix = test::gps_fix_at(frame, t, truth_m);
  fix.satellites_in_view = 10;
  for (int i = 0; i < 10; ++i) {
    auto& s = fix.satellites[static_cast<std::size_t>(i)];
    s.prn = i + 1;
    s.snr_dbhz = 40;
    s.used = true;
  }
  fix.satellites_used = 10;
  fix.hdop = 1.0;
  return fix;
}

struct Epochs {
  explicit Epochs(std::vector<Fault> faults) : frame(kOrigin), timeline(FaultPlan{std::move(faults), ""}, kStart) {}
  /// Epoch `s` seconds after the start with the truth at `truth_m`.
  nmea::Fix at(int s, const Enu& truth_m = {}) {
    const UtcNs t = kStart + seconds(s);
    nmea::Fix fix = make_fix(frame, t, truth_m);
    effect = test::apply_faults(timeline, t, fix, truth_m, frame, &rf);
    return fix;
  }
  /// The east offset of epoch `s`'s fix from the truth (metres).
  double east_m(int s, const Enu& truth_m = {}) {
    const nmea::Fix f = at(s, truth_m);
    return frame.to_enu({f.lat_deg, f.lon_deg, f.alt_msl_m}).east_m - truth_m.east_m;
  }
  LocalFrame frame;
  FaultTimeline timeline;
  RfState rf;
  EpochEffect effect;
};

Fault make(const FaultKeys& keys) { return make_fault(keys); }

TEST(FaultTriggers, AtUtcStartsAtThatEpoch) {
  Epochs run({make({{"kind", "outage"}, {"at_utc", "2026-03-01T10:00:03Z"}, {"duration", 2.0}})});
  EXPECT_TRUE(run.at(2).has_fix());
  EXPECT_FALSE(run.at(3).has_fix());
  EXPECT_FALSE(run.at(4).has_fix());
  EXPECT_TRUE(run.at(5).has_fix());
  EXPECT_EQ(run.timeline.entries()[0].epochs, 2u);
}

TEST(FaultTriggers, AtUtcBeforeTheStartIsOnFromTheStartWhileItLasts) {
  Epochs run({make({{"kind", "outage"}, {"at_utc", "2026-03-01T09:59:59Z"}, {"duration", 3.0}})});
  EXPECT_FALSE(run.at(0).has_fix());
  EXPECT_FALSE(run.at(1).has_fix());
  EXPECT_TRUE(run.at(2).has_fix());
}

TEST(FaultTriggers, AtUtcWithAtIsRefused) {
  EXPECT_THROW((void)make({{"kind", "outage"}, {"at", 2.0}, {"at_utc", "2026-03-01T10:00:03Z"}}), std::invalid_argument);
  EXPECT_THROW((void)make({{"kind", "outage"}, {"at_utc", "2026-03-01 10:00"}}), std::invalid_argument);
}

TEST(FaultTriggers, WhereCircleIsOnWhileTheTruthIsInsideAndAgainOnTheNextVisit) {
  // A circle of 100 m about a point 500 m east of the origin.
  LocalFrame frame(kOrigin);
  const Geodetic centre = frame.to_geodetic({500.0, 0.0, 0.0});
  Epochs run({make({{"kind", "outage"}, {"where", fmt::format("circle:{:.9f},{:.9f},100", centre.lat_deg, centre.lon_deg)}})});
  EXPECT_TRUE(run.at(0, {300.0, 0.0, 0.0}).has_fix());
  EXPECT_FALSE(run.at(1, {450.0, 0.0, 0.0}).has_fix());  // inside
  EXPECT_FALSE(run.at(2, {550.0, 0.0, 0.0}).has_fix());
  EXPECT_TRUE(run.at(3, {650.0, 0.0, 0.0}).has_fix());   // left
  EXPECT_FALSE(run.at(4, {500.0, 50.0, 0.0}).has_fix());  // back in
  EXPECT_TRUE(run.at(5, {500.0, 150.0, 0.0}).has_fix());
  EXPECT_EQ(run.timeline.entries()[0].epochs, 3u);
  EXPECT_FALSE(run.timeline.entries()[0].ended);
}

TEST(FaultTriggers, WherePolygonWithDurationEndsInsideAfterIt) {
  LocalFrame frame(kOrigin);
  const Geodetic a = frame.to_geodetic({100.0, -100.0, 0.0}), b = frame.to_geodetic({300.0, 100.0, 0.0});
  const std::string polygon = fmt::format("polygon:{0:.9f},{1:.9f};{0:.9f},{2:.9f};{3:.9f},{2:.9f};{3:.9f},{1:.9f}", a.lat_deg,
                                          a.lon_deg, b.lon_deg, b.lat_deg);
  Epochs run({make({{"kind", "outage"}, {"where", polygon}, {"duration", 2.0}})});
  EXPECT_TRUE(run.at(0, {50.0, 0.0, 0.0}).has_fix());
  EXPECT_FALSE(run.at(1, {150.0, 0.0, 0.0}).has_fix());
  EXPECT_FALSE(run.at(2, {200.0, 0.0, 0.0}).has_fix());
  EXPECT_TRUE(run.at(3, {250.0, 0.0, 0.0}).has_fix());  // still inside, its 2 s are over
}

TEST(FaultTriggers, RampOutFadesAWrongOffsetAsItFadedIn) {
  Epochs run({make({{"kind", "wrong"}, {"at", 2.0}, {"duration", 10.0}, {"east_m", 40.0}, {"ramp_s", 4.0}, {"ramp_out_s", 4.0}})});
  EXPECT_NEAR(run.east_m(1), 0.0, 1e-6);
  EXPECT_NEAR(run.east_m(2), 0.0, 1e-6);
  EXPECT_NEAR(run.east_m(4), 20.0, 1e-6);
  EXPECT_NEAR(run.east_m(6), 40.0, 1e-6);
  EXPECT_NEAR(run.east_m(11), 40.0, 1e-6);
  EXPECT_NEAR(run.east_m(12), 40.0, 1e-6);  // its end: fades from here
  EXPECT_NEAR(run.east_m(13), 30.0, 1e-6);
  EXPECT_NEAR(run.east_m(14), 20.0, 1e-6);
  EXPECT_NEAR(run.east_m(15), 10.0, 1e-6);
  EXPECT_NEAR(run.east_m(16), 0.0, 1e-6);
  EXPECT_NEAR(run.east_m(17), 0.0, 1e-6);
  EXPECT_TRUE(run.timeline.entries()[0].ended);
}

TEST(FaultTriggers, RampOutOfAJamRestoresTheRfStateAfterTheFade) {
  Epochs run({make({{"kind", "jam"}, {"at", 1.0}, {"duration", 2.0}, {"db", 10.0}, {"ramp_out_s", 2.0}})});
  (void)run.at(0);
  const RfState clean = run.rf;
  EXPECT_EQ(run.at(2).satellites[0].snr_dbhz, 30);
  EXPECT_EQ(run.at(3).satellites[0].snr_dbhz, 30);  // fading from its end
  EXPECT_EQ(run.at(4).satellites[0].snr_dbhz, 35);
  EXPECT_NE(run.rf.jamming_indicator, clean.jamming_indicator);
  EXPECT_EQ(run.at(5).satellites[0].snr_dbhz, 40);
  EXPECT_EQ(run.rf.jamming_indicator, clean.jamming_indicator);
}

TEST(FaultTriggers, RampOutIsRefusedForAKindThatDoesNotFade) {
  EXPECT_THROW((void)make({{"kind", "outage"}, {"ramp_out_s", 2.0}}), std::invalid_argument);
}

TEST(FaultTriggers, GarbleAndLatencyReachTheChannelAsEffects) {
  Epochs run({make({{"kind", "garble"}, {"at", 1.0}, {"duration", 1.0}, {"rate", 0.3}}),
           make({{"kind", "latency"}, {"at", 1.0}, {"delay_ms", 250.0}, {"jitter_ms", 50.0}})});
  (void)run.at(0);
  EXPECT_EQ(run.effect.garble_rate, 0.0);
  EXPECT_EQ(run.effect.delay_ms, 0.0);
  (void)run.at(1);
  EXPECT_EQ(run.effect.garble_rate, 0.3);
  EXPECT_EQ(run.effect.delay_ms, 250.0);
  EXPECT_EQ(run.effect.jitter_ms, 50.0);
  (void)run.at(2);
  EXPECT_EQ(run.effect.garble_rate, 0.0);
  EXPECT_EQ(run.effect.delay_ms, 250.0);
  EXPECT_THROW((void)make({{"kind", "garble"}, {"rate", 1.5}}), std::invalid_argument);
  EXPECT_THROW((void)make({{"kind", "garble"}}), std::invalid_argument);
  EXPECT_THROW((void)make({{"kind", "latency"}}), std::invalid_argument);
}

TEST(FaultTriggers, LiveEventsAreRecordedAtTheEpochTheyApply) {
  Epochs run({});
  (void)run.at(0);
  run.timeline.add_live(make({{"kind", "outage"}}), R"({"fault":"outage","receiver":0})");
  EXPECT_TRUE(run.timeline.applied_events().empty());
  EXPECT_FALSE(run.at(1).has_fix());
  ASSERT_EQ(run.timeline.applied_events().size(), 1u);
  EXPECT_EQ(run.timeline.applied_events()[0].since_s, 1.0);
  EXPECT_EQ(run.timeline.applied_events()[0].epoch, kStart + seconds(1));
  EXPECT_EQ(run.timeline.applied_events()[0].request, R"({"fault":"outage","receiver":0})");
  EXPECT_FALSE(run.at(2).has_fix());
  EXPECT_TRUE(run.timeline.applied_events().empty());
  EXPECT_EQ(run.timeline.clear(FaultKind::outage, R"({"clear":"outage","receiver":0})"), 1);
  EXPECT_TRUE(run.at(3).has_fix());
  ASSERT_EQ(run.timeline.applied_events().size(), 1u);
  EXPECT_EQ(run.timeline.applied_events()[0].since_s, 3.0);
}

}  // namespace fault_triggers_test
}  // namespace
}  // namespace gpsemu::faults
