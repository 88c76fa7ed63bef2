// NAV-RELPOSNED of a rover with a fixed base: relPos = rover - base (1005/1006) in the base's
// north/east/down, its length and accuracies, and the flags following the RTK state.
#include "emulator/rtk/static_base_relpos.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/nav.hpp"

namespace gpsemu::rtk {
namespace {
namespace static_base_relpos_test {

using Q = nmea::FixQuality;

constexpr double kBaseLatDeg = 43.0725, kBaseLonDeg = -89.4125, kBaseHeightM = 230.0;

BasePosition base() {
  BasePosition b;
  b.station_id = 42;
  GeographicLib::Geocentric::WGS84().Forward(kBaseLatDeg, kBaseLonDeg, kBaseHeightM, b.ecef_x_m, b.ecef_y_m, b.ecef_z_m);
  return b;
}

/// A rover fix `north`, `east` metres and `up` metres from the base (its local frame).
nmea::Fix rover_fix(double north_m, double east_m, double up_m) {
  const GeographicLib::LocalCartesian frame(kBaseLatDeg, kBaseLonDeg, kBaseHeightM);
  nmea::Fix fix;
  fix.quality = Q::rtk_fixed;
  double h_m = 0.0;
  frame.Reverse(east_m, north_m, up_m, fix.lat_deg, fix.lon_deg, h_m);
  fix.geoid_sep_m = -33.0;
  fix.alt_msl_m = h_m - fix.geoid_sep_m;
  fix.sigma_lat_m = 0.012;
  fix.sigma_lon_m = 0.010;
  fix.sigma_alt_m = 0.020;
  return fix;
}

RtkStatus status(Q quality) {
  RtkStatus s;
  s.quality = quality;
  s.correction_age_s = 0.4;
  s.station_id = 42;
  return s;
}

constexpr std::uint32_t kFixOk = 1u << 0, kDiff = 1u << 1, kValid = 1u << 2, kMoving = 1u << 5,
                        kRefPosMiss = 1u << 6, kRefObsMiss = 1u << 7, kHeadingValid = 1u << 8;
std::uint32_t carr(std::uint32_t flags) { return (flags >> 3) & 3u; }

ubx::RelPosNedFields encoded(const RtkStatus& s, const std::optional<BasePosition>& b, const nmea::Fix& fix) {
  return ubx::read_relposned(ubx::nav_relposned(fix, static_base_relpos(s, b, fix)));
}

TEST(StaticBaseRelPos, RtkFixedGivesTheRoverMinusTheBaseInTheBasesNed) {
  const nmea::Fix fix = rover_fix(300.0, -40.0, -2.5);
  const ubx::RelPosNedFields f = encoded(status(Q::rtk_fixed), base(), fix);
  EXPECT_EQ(f.version, 1);
  // cm and the 0.1 mm rest: within 0.2 mm of the geometry.
  EXPECT_NEAR(f.n_cm + f.hp_n * 0.01, 30000.0, 0.02);
  EXPECT_NEAR(f.e_cm + f.hp_e * 0.01, -4000.0, 0.02);
  EXPECT_NEAR(f.d_cm + f.hp_d * 0.01, 250.0, 0.02);
  EXPECT_NEAR(f.length_cm + f.hp_length * 0.01, std::sqrt(300.0 * 300.0 + 40.0 * 40.0 + 2.5 * 2.5) * 100.0, 0.02);
  EXPECT_EQ(f.acc_n, 120u);  // 0.1 mm: the fix's 1-sigma accuracies
  EXPECT_EQ(f.acc_e, 100u);
  EXPECT_EQ(f.acc_d, 200u);
  // Along a mostly-north baseline the length's accuracy is close to the north one.
  EXPECT_GT(f.acc_length, 110u);
  EXPECT_LE(f.acc_length, 120u);
  EXPECT_EQ(f.flags & (kFixOk | kDiff | kValid), kFixOk | kDiff | kValid);
  EXPECT_EQ(carr(f.flags), 2u);
  EXPECT_EQ(f.flags & (kMoving | kRefPosMiss | kRefObsMiss | kHeadingValid), 0u);
  EXPECT_EQ(f.heading_1e5deg, 0);
  EXPECT_EQ(f.acc_heading_1e5deg, 0u);
  const RelativePosition rel = static_base_relpos(status(Q::rtk_fixed), base(), fix);
  EXPECT_EQ(rel.ref_station_id, 42);
  EXPECT_FALSE(rel.is_moving);
}

TEST(StaticBaseRelPos, CarrSolnFollowsTheRtkState) {
  const nmea::Fix fix = rover_fix(10.0, 10.0, 0.0);
  const ubx::RelPosNedFields fl = encoded(status(Q::rtk_float), base(), fix);
  EXPECT_EQ(fl.flags & (kFixOk | kDiff | kValid), kFixOk | kDiff | kValid);
  EXPECT_EQ(carr(fl.flags), 1u);
  // DGPS: differential and a valid relative position (its accuracy the DGPS one), no carrier.
  const ubx::RelPosNedFields dg = encoded(status(Q::dgps), base(), fix);
  EXPECT_EQ(dg.flags & (kFixOk | kDiff | kValid), kFixOk | kDiff | kValid);
  EXPECT_EQ(carr(dg.flags), 0u);
  EXPECT_NEAR(dg.n_cm, 1000, 1);
}

// One accuracy for the rover's position (issue 36): in DGPS (the RTK part gives each axis at least
// 0.2 m) NAV-RELPOSNED's accN/accE/accD are NAV-PVT's hAcc and vAcc split by axis, not 283 mm
// against NAV-PVT's 300 mm.
TEST(StaticBaseRelPos, AccuraciesAreNavPvtsInDgps) {
  nmea::Fix fix = rover_fix(10.0, 10.0, 0.0);
  fix.quality = Q::dgps;
  fix.sigma_lat_m = fix.sigma_lon_m = 0.2;  // the DGPS floor of the RTK part
  fix.sigma_alt_m = 0.3;
  const ubx::RelPosNedFields rel = encoded(status(Q::dgps), base(), fix);
  const std::string pvt = ubx::nav_pvt(fix, {});
  const double h_acc_mm = ubx::get_u4(pvt, 40), v_acc_mm = ubx::get_u4(pvt, 44);
  EXPECT_NEAR(std::hypot(rel.acc_n, rel.acc_e) / 10.0, h_acc_mm, 1.0);
  EXPECT_NEAR(rel.acc_d / 10.0, v_acc_mm, 1.0);
  EXPECT_EQ(rel.acc_n, rel.acc_e);
}

TEST(StaticBaseRelPos, WithoutBasePositionOrCorrectionsNothingIsValid) {
  const nmea::Fix fix = rover_fix(10.0, 10.0, 0.0);
  // MSM without a 1005/1006: differential, but there is no base to be relative to.
  const ubx::RelPosNedFields no_base = encoded(status(Q::dgps), std::nullopt, fix);
  EXPECT_EQ(no_base.flags, kFixOk | kDiff);
  EXPECT_EQ(no_base.n_cm, 0);
  EXPECT_EQ(no_base.length_cm, 0);
  // Corrections timed out (the state back to the configured fix): only gnssFixOK.
  const ubx::RelPosNedFields stale = encoded(RtkStatus{}, base(), fix);
  EXPECT_EQ(stale.flags, kFixOk);
  EXPECT_EQ(stale.length_cm, 0);
  EXPECT_EQ(stale.acc_n, 0u);
  // No fix: nothing, not even gnssFixOK.
  nmea::Fix none = fix;
  none.quality = Q::none;
  const ubx::RelPosNedFields lost = encoded(status(Q::rtk_fixed), base(), none);
  EXPECT_EQ(lost.flags, 0u);
  EXPECT_EQ(lost.n_cm, 0);
}

TEST(StaticBaseRelPos, NedFromTheBaseIsItsLocalFrame) {
  const BasePosition b = base();
  const GeographicLib::LocalCartesian frame(kBaseLatDeg, kBaseLonDeg, kBaseHeightM);
  double lat = 0, lon = 0, h = 0, x = 0, y = 0, z = 0;
  frame.Reverse(1000.0, 2000.0, 50.0, lat, lon, h);  // east, north, up
  GeographicLib::Geocentric::WGS84().Forward(lat, lon, h, x, y, z);
  const NedOffset d = ned_from(b, x, y, z);
  EXPECT_NEAR(d.north_m, 2000.0, 1e-6);
  EXPECT_NEAR(d.east_m, 1000.0, 1e-6);
  EXPECT_NEAR(d.down_m, -50.0, 1e-6);
}

}  // namespace static_base_relpos_test
}  // namespace
}  // namespace gpsemu::rtk
