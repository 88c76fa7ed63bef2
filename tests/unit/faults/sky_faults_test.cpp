// The second stage of the catalogue on a fix: sky-mask (the satellites behind the mask leave the
// sky, DOPs from what is left, no fix under 4), spoof (position, velocity and time dragged
// together; NAV-STATUS spoofDetState), time (a jump, a week-number rollover) and reset (silent,
// then a reboot asked once); and their keys refused with the reason.
#include "emulator/faults/sky_faults.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "emulator/faults/control.hpp"
#include "emulator/faults/fault_timeline.hpp"
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/nav.hpp"
#include "tests/support/fault_fixes.hpp"

namespace gpsemu::faults {
namespace {
namespace sky_faults_test {

using std::chrono::seconds;

const Geodetic kOrigin{47.0, 8.0, 400.0};
const UtcNs kStart = parse_iso8601_utc("2024-05-01T12:00:00Z");
const Enu kTruth{10.0, -5.0, 2.0};
const Enu kError{0.6, -0.8, 1.0};

/// A 3-D fix of 12 used GPS satellites, one every 30 degrees of azimuth (0, 30, ... 330), at
/// elevations 15..70, moving north at 10 m/s; DOPs from that geometry.
nmea::Fix make_fix(const LocalFrame& frame, UtcNs t) {
  nmea::Fix fix = test::gps_fix_at(frame, t, kTruth + kError);
  fix.speed_mps = 10.0;
  fix.course_deg_true = 0.0;
  fix.satellites_in_view = 12;
  std::vector<sky::UsedSatellite> used;
  for (int i = 0; i < 12; ++i) {
    auto& s = fix.satellites[static_cast<std::size_t>(i)];
    s.prn = i + 1;
    s.sv_id = i + 1;
    s.azimuth_deg = 30 * i;
    s.elevation_deg = 15 + 5 * (i % 12);
    s.snr_dbhz = 40;
    s.used = true;
    used.push_back({double(s.azimuth_deg), double(s.elevation_deg), s.system});
  }
  const sky::Dops d = sky::multi_clock_dops(used);
  fix.satellites_used = 12;
  fix.hdop = d.hdop;
  fix.vdop = d.vdop;
  fix.pdop = d.pdop;
  fix.tdop = d.tdop;
  fix.gdop = d.gdop;
  fix.sigma_lat_m = fix.sigma_lon_m = 0.7 * d.hdop;
  fix.sigma_alt_m = 1.0 * d.vdop;
  return fix;
}

struct Epochs {
  explicit Epochs(std::vector<Fault> faults) : frame(kOrigin), timeline(FaultPlan{std::move(faults), ""}, kStart) {}
  nmea::Fix at(int s, EpochEffect* effect = nullptr) {
    const UtcNs t = kStart + seconds(s);
    nmea::Fix fix = make_fix(frame, t);
    const EpochEffect e = test::apply_faults(timeline, t, fix, kTruth, frame, &rf);
    if (effect) *effect = e;
    return fix;
  }
  double error_m(const nmea::Fix& fix) const {
    const Enu d = frame.to_enu({fix.lat_deg, fix.lon_deg, fix.alt_msl_m}) - kTruth;
    return std::hypot(d.east_m, d.north_m);
  }
  LocalFrame frame;
  FaultTimeline timeline;
  RfState rf;
};

Fault fault_of(FaultKeys keys) { return make_fault(keys); }
/// The sectors of a sky-mask fault with `mask` (a preset or FROM-TO:ELEV sectors).
std::vector<SkyMaskSector> mask_of(const std::string& mask) {
  return std::get<SkyMask>(fault_of({{"kind", std::string("sky-mask")}, {"mask", mask}}).params).mask;
}

TEST(SkyMaskFault, SatellitesBehindTheMaskLeaveTheSkyAndTheDopsFollowTheRest) {
  Epochs run({fault_of({{"kind", std::string("sky-mask")}, {"at", 1.0}, {"duration", 2.0}, {"mask", std::string("0-180:90")}})});
  const nmea::Fix before = run.at(0);
  const nmea::Fix f = run.at(1);
  ASSERT_TRUE(f.has_fix());
  EXPECT_EQ(f.satellites_in_view, 6);  // azimuths 180..330 are left
  EXPECT_EQ(f.satellites_used, 6);
  for (int i = 0; i < f.satellites_in_view; ++i) EXPECT_GE(f.satellites[static_cast<std::size_t>(i)].azimuth_deg, 180);
  // The DOPs of the six left, computed from their geometry.
  std::vector<sky::UsedSatellite> left;
  for (int i = 6; i < 12; ++i) left.push_back({30.0 * i, 15.0 + 5 * i, nmea::GnssSystem::gps});
  const sky::Dops d = sky::multi_clock_dops(left);
  EXPECT_NEAR(f.hdop, d.hdop, 1e-9);
  EXPECT_NEAR(f.vdop, d.vdop, 1e-9);
  EXPECT_NEAR(f.pdop, d.pdop, 1e-9);
  EXPECT_GT(f.hdop, 1.5 * before.hdop);
  EXPECT_NEAR(f.sigma_lat_m / before.sigma_lat_m, f.hdop / before.hdop, 1e-9);
  EXPECT_NEAR(run.error_m(f) / run.error_m(before), f.hdop / before.hdop, 1e-6);
  const nmea::Fix after = run.at(3);
  EXPECT_EQ(after.satellites_in_view, 12);
  EXPECT_DOUBLE_EQ(after.hdop, before.hdop);
}

TEST(SkyMaskFault, FewerThanFourLeftLoseTheFixAndTheMaskPresetsParse) {
  // tunnel-entry: only the window 330..30 degrees above 10 is left: satellites at 0 and 330.
  Epochs run({fault_of({{"kind", std::string("sky-mask")}, {"at", 1.0}, {"mask", std::string("tunnel-entry")}})});
  EXPECT_TRUE(run.at(0).has_fix());
  const nmea::Fix f = run.at(1);
  EXPECT_FALSE(f.has_fix());
  EXPECT_EQ(f.satellites_in_view, 2);
  EXPECT_EQ(f.satellites_used, 0);
  for (int i = 0; i < f.satellites_in_view; ++i) EXPECT_FALSE(f.satellites[static_cast<std::size_t>(i)].used);
  EXPECT_EQ(mask_of("urban-canyon").size(), 4u);
  EXPECT_EQ(mask_of("tree-line").size(), 1u);
  EXPECT_TRUE(masked(mask_of("tree-line"), 270, 29));
  EXPECT_FALSE(masked(mask_of("tree-line"), 90, 5));
}

TEST(SpoofFault, PositionVelocityAndTimeAreDraggedTogether) {
  Epochs run({fault_of({{"kind", std::string("spoof")}, {"at", 2.0}, {"duration", 10.0}, {"speed_mps", 5.0},
                        {"bearing_deg", 90.0}, {"time_drift_ms_per_s", 20.0}, {"detected", std::string("true")}})});
  const nmea::Fix clean = run.at(0);
  EXPECT_EQ(run.rf.spoof_detection_state, 0);
  for (int k = 2; k < 6; ++k) {
    const nmea::Fix f = run.at(k);
    const Enu p = run.frame.to_enu({f.lat_deg, f.lon_deg, f.alt_msl_m}) - kTruth;
    EXPECT_NEAR(p.east_m - kError.east_m, 5.0 * (k - 2), 1e-6) << k;  // 5 m/s east
    EXPECT_NEAR(p.north_m, kError.north_m, 1e-6) << k;
    EXPECT_NEAR(f.speed_mps, std::hypot(10.0, 5.0), 1e-9) << k;  // north 10 m/s + east 5 m/s
    EXPECT_NEAR(*f.course_deg_true, std::atan2(5.0, 10.0) * 180.0 / M_PI, 1e-9) << k;
    EXPECT_EQ(f.time_utc - clean.time_utc, std::chrono::milliseconds(1000 * k + 20 * (k - 2))) << k;
    EXPECT_EQ(run.rf.spoof_detection_state, 3) << "detected: multiple spoofing indications";
  }
  (void)run.at(12);
  EXPECT_EQ(run.rf.spoof_detection_state, 0) << "clean again after the spoof";
  Epochs quiet({fault_of({{"kind", std::string("spoof")}, {"east_m", 50.0}, {"ramp_s", 10.0}})});
  const nmea::Fix f = quiet.at(5);
  EXPECT_EQ(quiet.rf.spoof_detection_state, 1) << "undetected: no spoofing indicated";
  EXPECT_NEAR(quiet.frame.to_enu({f.lat_deg, f.lon_deg, f.alt_msl_m}).east_m - kTruth.east_m - kError.east_m, 25.0, 1e-6);
}

TEST(SpoofFault, NavStatusReportsTheSpoofDetectionState) {
  ubx::NavExtras extras;
  nmea::Fix fix;
  EXPECT_EQ(ubx::get_u1(ubx::nav_status(fix, extras), 7) >> 3 & 3, 0);
  extras.rf.spoof_detection_state = 3;
  EXPECT_EQ(ubx::get_u1(ubx::nav_status(fix, extras), 7) >> 3 & 3, 3);
  extras.rf.spoof_detection_state = 1;
  EXPECT_EQ(ubx::get_u1(ubx::nav_status(fix, extras), 7) >> 3 & 3, 1);
}

TEST(TimeFault, AJumpStepsTheTimeAndARolloverTakesTheDate1024WeeksBack) {
  Epochs jump({fault_of({{"kind", std::string("time")}, {"mode", std::string("jump")}, {"jump_s", -3.5},
                         {"at", 1.0}, {"duration", 2.0}})});
  EXPECT_EQ(jump.at(0).time_utc, std::chrono::floor<std::chrono::milliseconds>(kStart));
  EXPECT_EQ(jump.at(1).time_utc, std::chrono::floor<std::chrono::milliseconds>(kStart + seconds(1)) - std::chrono::milliseconds(3500));
  EXPECT_EQ(jump.at(3).time_utc, std::chrono::floor<std::chrono::milliseconds>(kStart + seconds(3)));
  Epochs roll({fault_of({{"kind", std::string("time")}, {"mode", std::string("rollover")}})});
  const nmea::Fix f = roll.at(0);
  // 2024-05-01 less 1024 weeks: 2004-09-15, GPS week 2312 - 1024 = 1288.
  EXPECT_EQ(std::chrono::year_month_day{std::chrono::floor<std::chrono::days>(f.time_utc)},
            std::chrono::year{2004} / 9 / 15);
  EXPECT_EQ(ubx::gps_time(f.time_utc).week, ubx::gps_time(make_fix(roll.frame, kStart).time_utc).week - 1024);
  EXPECT_TRUE(f.has_fix());
}

TEST(ResetFault, SilentForItsBootThenARebootAskedOnceAndTheFaultLastsToTheTtff) {
  const Fault reset = fault_of({{"kind", std::string("reset")}, {"at", 2.0}, {"silent_s", 2.0}, {"ttff_s", 3.0}});
  ASSERT_TRUE(reset.duration_s.has_value());
  EXPECT_DOUBLE_EQ(*reset.duration_s, 5.0);
  Epochs run({reset});
  EpochEffect e;
  (void)run.at(1, &e);
  EXPECT_FALSE(e.silent);
  EXPECT_FALSE(e.reboot_cold_start_s);
  (void)run.at(2, &e);
  EXPECT_TRUE(e.silent);
  ASSERT_TRUE(e.reboot_cold_start_s.has_value());
  EXPECT_DOUBLE_EQ(*e.reboot_cold_start_s, 5.0) << "the boot and the TTFF, from the reset";
  (void)run.at(3, &e);
  EXPECT_TRUE(e.silent);
  EXPECT_FALSE(e.reboot_cold_start_s) << "asked once";
  (void)run.at(4, &e);
  EXPECT_FALSE(e.silent);
  EXPECT_EQ(run.timeline.entries()[0].epochs, 3u);
  (void)run.at(7, &e);
  EXPECT_TRUE(run.timeline.entries()[0].ended);
  EXPECT_EQ(run.timeline.entries()[0].epochs, 3u);
}

TEST(SecondStageFaults, BadKeysAreRefusedWithTheReason) {
  const auto refused = test::expect_fault_refused;
  refused({{"kind", std::string("sky-mask")}}, "mask: missing");
  refused({{"kind", std::string("sky-mask")}, {"mask", std::string("0-90")}}, "mask: sky-mask: '0-90' is not FROM-TO:ELEVATION");
  refused({{"kind", std::string("spoof")}}, "spoof: give speed_mps");
  refused({{"kind", std::string("spoof")}, {"speed_mps", 3.0}, {"detected", std::string("maybe")}}, "detected: expected true or false");
  refused({{"kind", std::string("spoof")}, {"speed_mps", 3.0}, {"bearing_deg", 400.0}}, "bearing_deg: 400 is outside [0, 360]");
  refused({{"kind", std::string("time")}}, "mode: missing");
  refused({{"kind", std::string("time")}, {"mode", std::string("leap")}}, "mode: expected jump, rollover or leap-second");
  refused({{"kind", std::string("time")}, {"mode", std::string("jump")}}, "jump_s: missing");
  refused({{"kind", std::string("time")}, {"mode", std::string("jump")}, {"jump_s", 0.0001}}, "whole number of milliseconds");
  refused({{"kind", std::string("reset")}, {"duration", 5.0}}, "reset: an event");
  refused({{"kind", std::string("reset")}, {"db", 5.0}}, "db: not a parameter of reset (its parameters: silent_s, ttff_s");
  EXPECT_EQ(make_fault({{"kind", std::string("spoof")}, {"speed_mps", 2.0}, {"detected", 1.0}}).describe(),
            "spoof speed_mps=2 bearing_deg=0 detected at 0 s to the end");
}

TEST(SecondStageFaults, LiveControlTakesTheNewKindsWithJsonBooleans) {
  Epochs run({});
  FaultControl control({&run.timeline});
  const std::string spoof = control.handle(R"({"fault":"spoof","speed_mps":3,"detected":true,"duration":2})");
  EXPECT_NE(spoof.find(R"("class":"FAULT")"), std::string::npos) << spoof;
  EXPECT_NE(spoof.find("spoof speed_mps=3 bearing_deg=0 detected for 2 s"), std::string::npos) << spoof;
  const std::string mask = control.handle(R"({"fault":"sky-mask","mask":"180-360:60"})");
  EXPECT_NE(mask.find(R"("class":"FAULT")"), std::string::npos) << mask;
  const std::string reset = control.handle(R"({"fault":"reset","duration":3})");
  EXPECT_NE(reset.find(R"("class":"ERROR")"), std::string::npos) << reset;
  EXPECT_NE(reset.find("reset: an event"), std::string::npos) << reset;
  const nmea::Fix f = run.at(1);
  EXPECT_EQ(run.rf.spoof_detection_state, 3);
  EXPECT_EQ(f.satellites_in_view, 9) << "azimuths 180, 210, 240 at 45..55 degrees hidden";
}

}  // namespace sky_faults_test
}  // namespace
}  // namespace gpsemu::faults
