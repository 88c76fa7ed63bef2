// Each fault's effect on a fix (and a u-blox's RF state), at the epochs it covers.
#include "emulator/faults/fault_timeline.hpp"
#include "emulator/faults/sky_faults.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "emulator/model/receiver.hpp"
#include "tests/support/fault_fixes.hpp"

namespace gpsemu::faults {
namespace {
namespace fault_timeline_test {

using std::chrono::seconds;

const Geodetic kOrigin{47.0, 8.0, 400.0};
const UtcNs kStart = UtcNs{std::chrono::duration_cast<UtcNs::duration>(std::chrono::hours(24 * 20000))};
const Enu kTruth{10.0, -5.0, 2.0};
const Enu kError{0.6, -0.8, 1.0};  // the receiver model's error: 1 m horizontally

/// A 3-D gps fix of 10 used satellites (C/N0 30..48 dB-Hz) at kTruth + kError, spread over the sky,
/// its DOPs those of their geometry.
nmea::Fix make_fix(const LocalFrame& frame, UtcNs t) {
  nmea::Fix fix = test::gps_fix_at(frame, t, kTruth + kError);
  fix.satellites_in_view = 12;
  for (int i = 0; i < 12; ++i) {
    auto& s = fix.satellites[static_cast<std::size_t>(i)];
    s.prn = i + 1;
    s.snr_dbhz = 26 + 2 * i;  // 26..48
    s.used = i >= 2;          // the 10 strongest
    s.azimuth_deg = (97 * i) % 360;
    s.elevation_deg = 10 + (37 * i) % 75;
  }
  fix.satellites_used = 10;
  const sky::Dops dops = used_dops(fix);
  fix.hdop = dops.hdop;
  fix.vdop = dops.vdop;
  fix.pdop = dops.pdop;
  fix.tdop = dops.tdop;
  fix.gdop = dops.gdop;
  fix.sigma_lat_m = 0.8;
  fix.sigma_lon_m = 0.6;
  fix.sigma_alt_m = 1.0;
  fix.range_rms_m = 0.5;
  return fix;
}

Enu error_of(const nmea::Fix& fix, const LocalFrame& frame) {
  return frame.to_enu({fix.lat_deg, fix.lon_deg, fix.alt_msl_m}) - kTruth;
}

struct Epochs {
  explicit Epochs(std::vector<Fault> faults) : frame(kOrigin), timeline(FaultPlan{std::move(faults), ""}, kStart) {}
  /// Epoch `s` seconds after the start, through the timeline.
  nmea::Fix at(int s, bool* silent = nullptr) {
    const UtcNs t = kStart + seconds(s);
    nmea::Fix fix = make_fix(frame, t);
    const EpochEffect e = test::apply_faults(timeline, t, fix, kTruth, frame, &rf);
    if (silent) *silent = e.silent;
    return fix;
  }
  LocalFrame frame;
  FaultTimeline timeline;
  RfState rf;
};

Fault fault(FaultParams params, double at_s, double duration_s) {
  Fault f;
  f.params = std::move(params);
  f.at_s = at_s;
  f.duration_s = duration_s;
  return f;
}

TEST(FaultTimeline, OutageLeavesNoSatellitesAndNoFixThenReturns) {
  Epochs run({fault(Outage{}, 2, 3)});
  EXPECT_TRUE(run.at(1).has_fix());
  for (int s = 2; s < 5; ++s) {
    const nmea::Fix f = run.at(s);
    EXPECT_FALSE(f.has_fix()) << s;
    EXPECT_EQ(f.satellites_in_view, 0);
    EXPECT_EQ(f.satellites_used, 0);
    EXPECT_EQ(f.time_utc, std::chrono::floor<std::chrono::milliseconds>(kStart + seconds(s)));
  }
  EXPECT_TRUE(run.at(5).has_fix());
  EXPECT_EQ(run.timeline.entries()[0].epochs, 3u);
}

TEST(FaultTimeline, FreezeRepeatsTheLastFixWithNewTimes) {
  Epochs run({fault(Freeze{}, 2, 2)});
  const nmea::Fix before = run.at(1);
  const nmea::Fix frozen = run.at(2);
  EXPECT_DOUBLE_EQ(frozen.lat_deg, before.lat_deg);
  EXPECT_DOUBLE_EQ(frozen.lon_deg, before.lon_deg);
  EXPECT_EQ(frozen.time_utc - before.time_utc, std::chrono::milliseconds(1000));
  EXPECT_EQ(run.at(3).time_utc - before.time_utc, std::chrono::milliseconds(2000));
}

TEST(FaultTimeline, JumpStepsByItsOffsetAndDecays) {
  Fault jump = fault(Jump{.offset_m = {20.0, -10.0, 5.0}, .decay_s = {}}, 2, 10);
  Fault decaying = fault(Jump{.offset_m = {10.0, 0.0, 0.0}, .decay_s = 2.0}, 20, 10);
  Epochs run({jump, decaying});
  const Enu e1 = error_of(run.at(1), run.frame);
  EXPECT_NEAR(e1.east_m, kError.east_m, 1e-6);
  const Enu e2 = error_of(run.at(2), run.frame);
  EXPECT_NEAR(e2.east_m, kError.east_m + 20.0, 1e-6);
  EXPECT_NEAR(e2.north_m, kError.north_m - 10.0, 1e-6);
  EXPECT_NEAR(e2.up_m, kError.up_m + 5.0, 1e-6);
  EXPECT_NEAR(error_of(run.at(20), run.frame).east_m, kError.east_m + 10.0, 1e-6);
  EXPECT_NEAR(error_of(run.at(22), run.frame).east_m, kError.east_m + 10.0 * std::exp(-1.0), 1e-6);
  EXPECT_NEAR(error_of(run.at(30), run.frame).east_m, kError.east_m, 1e-6);
}

TEST(FaultTimeline, WrongIsAConstantOffsetRampedIn) {
  Fault wrong = fault(Wrong{.offset_m = {0.0, 50.0, 0.0}}, 0, 100);
  wrong.ramp_s = 10.0;
  Epochs run({wrong});
  EXPECT_NEAR(error_of(run.at(5), run.frame).north_m, kError.north_m + 25.0, 1e-6);
  EXPECT_NEAR(error_of(run.at(10), run.frame).north_m, kError.north_m + 50.0, 1e-6);
  EXPECT_NEAR(error_of(run.at(60), run.frame).north_m, kError.north_m + 50.0, 1e-6);
}

TEST(FaultTimeline, FixQualityForcesTheQualityAndScalesTheAccuracy) {
  Fault q = fault(ForcedQuality{.quality = nmea::FixQuality::rtk_fixed}, 0, 10);
  Epochs run({q});
  const nmea::Fix f = run.at(1);
  EXPECT_EQ(f.quality, nmea::FixQuality::rtk_fixed);
  // 0.8 m x 0.01 = 8 mm, raised to RTK fixed's floor of 1 cm (the floor of the new quality, once).
  EXPECT_NEAR(f.sigma_lat_m, 0.01, 1e-12);
  EXPECT_NEAR(f.sigma_alt_m, 0.015, 1e-12);
  EXPECT_NEAR(error_of(f, run.frame).east_m, kError.east_m * noise_scale(nmea::FixQuality::rtk_fixed), 1e-6);
  EXPECT_DOUBLE_EQ(f.hdop, make_fix(run.frame, kStart).hdop);  // the geometry is the same
}

TEST(FaultTimeline, DegradeUsesFewerSatellitesWithLargerDopAndError) {
  Fault d = fault(Degrade{.satellites = 5, .dop_k = {}, .noise_k = 3.0}, 0, 10);
  Epochs run({d});
  const nmea::Fix f = run.at(1);
  EXPECT_EQ(f.satellites_used, 5);
  int used = 0;
  for (int i = 0; i < f.satellites_in_view; ++i) used += f.satellites[static_cast<std::size_t>(i)].used;
  EXPECT_EQ(used, 5);
  EXPECT_TRUE(f.satellites[11].used);  // the strongest stay
  EXPECT_FALSE(f.satellites[2].used);
  EXPECT_NEAR(f.hdop, used_dops(f).hdop, 1e-9);  // the geometry of the five left
  EXPECT_NEAR(f.vdop, used_dops(f).vdop, 1e-9);
  EXPECT_GT(f.hdop, make_fix(run.frame, kStart).hdop * 1.2);
  EXPECT_NEAR(error_of(f, run.frame).east_m, 3.0 * kError.east_m, 1e-6);
  EXPECT_NEAR(f.sigma_lon_m, 3.0 * 0.6, 1e-12);

  Fault too_few = fault(Degrade{.satellites = 3, .dop_k = {}, .noise_k = {}}, 0, 10);
  Epochs lost({too_few});
  const nmea::Fix g = lost.at(1);
  EXPECT_FALSE(g.has_fix());
  EXPECT_EQ(g.satellites_in_view, 12);  // still tracked
  EXPECT_EQ(g.satellites_used, 0);
}

TEST(FaultTimeline, SilenceWritesNothingForItsDuration) {
  Epochs run({fault(Silence{}, 2, 2)});
  bool silent = true;
  (void)run.at(1, &silent);
  EXPECT_FALSE(silent);
  (void)run.at(2, &silent);
  EXPECT_TRUE(silent);
  (void)run.at(3, &silent);
  EXPECT_TRUE(silent);
  (void)run.at(4, &silent);
  EXPECT_FALSE(silent);
}

TEST(FaultTimeline, JamLowersCn0DropsWeakSatellitesAndLosesTheFix) {
  Fault jam = fault(Jam{.db = 25.0, .leave = {}}, 10, 20);
  jam.ramp_s = 10.0;
  Epochs run({jam});
  const RfState clean = run.rf;
  EXPECT_EQ(run.at(10).satellites_used, 10);  // the ramp starts at 0 dB
  // 12.5 dB down: C/N0 26..48 -> 13.5..35.5; 30 and 32 fall under 20 dB-Hz and leave the solution.
  const nmea::Fix f = run.at(15);
  EXPECT_EQ(f.satellites[0].snr_dbhz, std::nullopt);
  EXPECT_EQ(f.satellites[2].snr_dbhz, std::nullopt);
  EXPECT_FALSE(f.satellites[2].used);
  EXPECT_FALSE(f.satellites[3].used);
  EXPECT_TRUE(f.satellites[4].used);
  EXPECT_EQ(f.satellites[11].snr_dbhz, 36);
  EXPECT_EQ(f.satellites_used, 8);
  EXPECT_TRUE(f.has_fix());
  const double hdop_before = make_fix(run.frame, kStart).hdop;
  EXPECT_NEAR(f.hdop, used_dops(f).hdop, 1e-9);  // the geometry of the eight left
  EXPECT_GT(f.hdop, hdop_before);
  const double error_k = f.hdop / hdop_before * std::pow(10.0, 12.5 / 20.0);
  EXPECT_NEAR(f.sigma_lat_m, 0.8 * error_k, 1e-9);
  EXPECT_NEAR(error_of(f, run.frame).north_m, kError.north_m * error_k, 1e-6);
  EXPECT_EQ(run.rf.jamming_state, 2);  // warning
  EXPECT_GT(run.rf.jamming_indicator, clean.jamming_indicator);
  EXPECT_LT(run.rf.agc_count, clean.agc_count);
  // 25 dB down: only 46 and 48 stay above 20 dB-Hz: no fix, both still tracked.
  const nmea::Fix lost = run.at(20);
  EXPECT_FALSE(lost.has_fix());
  EXPECT_EQ(lost.satellites_used, 0);
  EXPECT_EQ(lost.satellites[11].snr_dbhz, 23);
  EXPECT_EQ(run.rf.jamming_state, 3);  // critical
  // After the jam: the clean sky and RF front end.
  const nmea::Fix after = run.at(30);
  EXPECT_EQ(after.satellites_used, 10);
  EXPECT_EQ(run.rf.jamming_state, clean.jamming_state);
  EXPECT_EQ(run.rf.agc_count, clean.agc_count);
  EXPECT_EQ(run.timeline.entries()[0].epochs, 3u);
}

TEST(FaultTimeline, JamLeavingNSatellitesTakesItsStrengthFromTheSkyOfTheEpoch) {
  // C/N0 26..48: leaving 3 needs 42 under 20 dB-Hz, 22.5 dB; 48, 46 and 44 stay (26, 24, 22).
  Fault lose_fix = fault(Jam{.db = 0.0, .leave = 3}, 10, 20);
  EXPECT_EQ(lose_fix.describe().find("jam leave=3"), 0u) << lose_fix.describe();
  Epochs run({lose_fix});
  const nmea::Fix lost = run.at(12);
  EXPECT_FALSE(lost.has_fix());
  EXPECT_EQ(lost.satellites[11].snr_dbhz, 26);
  EXPECT_EQ(lost.satellites[9].snr_dbhz, 22);
  EXPECT_EQ(lost.satellites[8].snr_dbhz, std::nullopt);
  EXPECT_EQ(run.rf.jamming_state, 3);  // 22.5 dB: critical
  // Leaving 6: the 6 strongest (38..48) tracked and used (a fix), the drop 36 - 20 + 0.5 = 16.5 dB.
  Epochs six({fault(Jam{.db = 0.0, .leave = 6}, 10, 20)});
  const nmea::Fix kept = six.at(12);
  EXPECT_TRUE(kept.has_fix());
  EXPECT_EQ(kept.satellites_used, 6);
  EXPECT_EQ(kept.satellites[6].snr_dbhz, 22);
  EXPECT_EQ(kept.satellites[5].snr_dbhz, std::nullopt);
}

TEST(FaultTimeline, ScenarioOrderAppliesAndOnlyActiveFaultsCount) {
  Fault jump = fault(Jump{.offset_m = {5.0, 0.0, 0.0}, .decay_s = {}}, 0, 5);
  Epochs run({jump, fault(Outage{}, 3, 1)});
  EXPECT_NEAR(error_of(run.at(2), run.frame).east_m, kError.east_m + 5.0, 1e-6);
  EXPECT_FALSE(run.at(3).has_fix());  // the outage wins over the jump
  EXPECT_EQ(run.timeline.entries()[0].epochs, 2u);
  EXPECT_EQ(run.timeline.entries()[1].epochs, 1u);
}

TEST(FaultTimeline, ASpoofWithRampOutReturnsGraduallyInsteadOfSnappingBack) {
  // 10 m/s east for 5 s, then back over 5 s: never more than one epoch's drag (10 m) at a time.
  const Fault spoof = make_fault({{"kind", std::string("spoof")}, {"at", 0.0}, {"duration", 5.0}, {"speed_mps", 10.0},
                                  {"bearing_deg", 90.0}, {"ramp_out_s", 5.0}});
  Epochs run({spoof});
  std::vector<double> east_m;
  for (int s = 0; s <= 11; ++s) east_m.push_back(error_of(run.at(s), run.frame).east_m - kError.east_m);
  EXPECT_NEAR(east_m[4], 40.0, 1e-3);
  EXPECT_NEAR(east_m[5], 50.0, 1e-3);  // the fade starts where the drag had got to
  EXPECT_NEAR(east_m[6], 40.0, 1e-3);
  EXPECT_NEAR(east_m[8], 20.0, 1e-3);
  EXPECT_NEAR(east_m[10], 0.0, 1e-3);
  EXPECT_NEAR(east_m[11], 0.0, 1e-3);
  for (std::size_t k = 1; k < east_m.size(); ++k) EXPECT_LE(std::abs(east_m[k] - east_m[k - 1]), 10.0 + 1e-3) << k;
  EXPECT_EQ(run.timeline.entries()[0].epochs, 10u);  // 5 on, 5 fading (the last at strength 0 included)
}

}  // namespace fault_timeline_test
}  // namespace
}  // namespace gpsemu::faults
