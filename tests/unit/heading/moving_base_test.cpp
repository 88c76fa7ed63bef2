// The moving-base pair's geometry and the rover's NAV-RELPOSNED values: the baseline turns with
// the yaw, the heading is the baseline's within its stated accuracy, nothing is valid without the
// base's corrections or a yaw; the role and antenna offset settings refuse bad text.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "emulator/heading/moving_base.hpp"

namespace gpsemu::heading {
namespace {
namespace moving_base_test {

using namespace std::chrono_literals;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

double angle_diff_deg(double a, double b) { return std::remainder(a - b, 360.0); }

TEST(MovingBase, BaselineTurnsWithTheYaw) {
  const AntennaOffset base{-0.5, 0.0, 0.0}, rover{0.5, 0.0, 0.0};  // 1 m fore-aft
  const Ned north = baseline_ned(base, rover, 0.0);
  EXPECT_NEAR(north.north_m, 1.0, 1e-12);
  EXPECT_NEAR(north.east_m, 0.0, 1e-12);
  const Ned east = baseline_ned(base, rover, 90.0);
  EXPECT_NEAR(east.north_m, 0.0, 1e-12);
  EXPECT_NEAR(east.east_m, 1.0, 1e-12);
  // A right-left baseline points 90 degrees right of the yaw.
  const Ned side = baseline_ned({0.0, -0.4, 0.0}, {0.0, 0.4, -0.1}, 30.0);
  EXPECT_NEAR(std::atan2(side.east_m, side.north_m) * 180.0 / M_PI, 120.0, 1e-9);
  EXPECT_NEAR(side.down_m, -0.1, 1e-12);
  const Enu up = offset_enu({0.0, 0.0, -1.5}, 10.0);
  EXPECT_NEAR(up.up_m, 1.5, 1e-12);
}

MovingBaseOptions rover_options() {
  MovingBaseOptions o;
  o.role = Role::rover;
  o.base_antenna = {-0.6, 0.0, 0.0};
  o.antenna = {0.6, 0.0, 0.0};
  return o;
}

TEST(MovingBase, RoverHeadingIsTheYawWithinItsAccuracy) {
  RoverRelPos rover(rover_options(), 7);
  int outside_3_sigma = 0;
  double sum_squared_error = 0.0;
  for (int k = 0; k < 720; ++k) {
    const UtcNs t = kT0 + k * 100ms;
    sources::Truth truth;
    truth.yaw_deg = std::fmod(k * 0.5, 360.0);
    const RelativePosition rel = rover.at(t, truth, t - 100ms);
    ASSERT_TRUE(rel.rel_pos_valid);
    ASSERT_TRUE(rel.heading_valid);
    EXPECT_EQ(rel.carrier, CarrierSolution::fixed);
    EXPECT_TRUE(rel.diff_soln);
    EXPECT_NEAR(rel.length_m, 1.2, 0.06);
    // 1 cm over 1.2 m: 0.48 degrees 1 sigma
    EXPECT_NEAR(rel.acc_heading_deg, std::atan2(0.01, 1.2) * 180.0 / M_PI, 1e-9);
    const double error_deg = angle_diff_deg(rel.heading_deg, *truth.yaw_deg);
    sum_squared_error += error_deg * error_deg;
    if (std::abs(error_deg) > 3.0 * rel.acc_heading_deg) ++outside_3_sigma;
  }
  // The stated accuracy is the error's: RMS within 10 % of it (4 sigma of the estimate over 720),
  // and few beyond 3 of it (0.27 % expected: 2 of 720; at most 1 %).
  const double sigma_deg = std::atan2(0.01, 1.2) * 180.0 / M_PI;
  EXPECT_NEAR(std::sqrt(sum_squared_error / 720.0) / sigma_deg, 1.0, 0.1);
  EXPECT_LE(outside_3_sigma, 7);
}

TEST(MovingBase, NothingValidWithoutCorrectionsOrYaw) {
  RoverRelPos rover(rover_options(), 1);
  sources::Truth truth;
  truth.yaw_deg = 45.0;
  EXPECT_FALSE(rover.at(kT0, truth, std::nullopt).rel_pos_valid);
  EXPECT_TRUE(rover.at(kT0 + 1500ms, truth, kT0).rel_pos_valid);   // 1.5 s old: still in time
  EXPECT_FALSE(rover.at(kT0 + 1600ms, truth, kT0).rel_pos_valid);  // older: the base is lost
  const RelativePosition lost = rover.at(kT0 + 2s, truth, kT0);
  EXPECT_TRUE(lost.is_moving);
  EXPECT_FALSE(lost.diff_soln);
  EXPECT_EQ(lost.carrier, CarrierSolution::none);
  EXPECT_FALSE(rover.at(kT0, sources::Truth{}, kT0).rel_pos_valid);  // no yaw: no baseline
  EXPECT_FALSE(rover.at(kT0, std::nullopt, kT0).rel_pos_valid);
}

TEST(MovingBase, AVerticalBaselineHasNoHeading) {
  MovingBaseOptions o = rover_options();
  o.base_antenna = {0.0, 0.0, 0.0};
  o.antenna = {0.0, 0.0, -1.0};
  RoverRelPos rover(o, 1);
  sources::Truth truth;
  truth.yaw_deg = 10.0;
  const RelativePosition rel = rover.at(kT0, truth, kT0);
  EXPECT_TRUE(rel.rel_pos_valid);
  EXPECT_FALSE(rel.heading_valid);
}

TEST(MovingBase, SettingsTextIsChecked) {
  EXPECT_EQ(parse_role("rover"), Role::rover);
  EXPECT_EQ(parse_role("moving-base"), Role::moving_base);
  EXPECT_THROW((void)parse_role("base"), std::invalid_argument);
  const AntennaOffset a = parse_antenna_offset("0.5, -0.25,0");
  EXPECT_DOUBLE_EQ(a.forward_m, 0.5);
  EXPECT_DOUBLE_EQ(a.right_m, -0.25);
  EXPECT_DOUBLE_EQ(a.down_m, 0.0);
  for (const char* bad : {"1,2", "1,2,3,4", "1,x,3", "1,,3", "1,2,300", "nan,0,0"}) {
    EXPECT_THROW((void)parse_antenna_offset(bad), std::invalid_argument) << bad;
  }
  try {
    (void)parse_antenna_offset("1,2");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("antenna-offset"), std::string::npos);
  }
}

// Pitch and roll tilt the baseline: its down part and length follow the attitude, the heading
// stays that of its horizontal part.
TEST(MovingBase, PitchAndRollTiltTheBaseline) {
  const AntennaOffset base{-0.5, 0.0, 0.0}, rover{0.5, 0.0, 0.0};  // 1 m fore-aft
  const double s10 = std::sin(10.0 * M_PI / 180.0), c10 = std::cos(10.0 * M_PI / 180.0);
  const Ned nose_up = baseline_ned(base, rover, 90.0, 10.0, 0.0);  // facing east, nose 10 degrees up
  EXPECT_NEAR(nose_up.east_m, c10, 1e-12);
  EXPECT_NEAR(nose_up.north_m, 0.0, 1e-12);
  EXPECT_NEAR(nose_up.down_m, -s10, 1e-12);  // the front antenna is higher
  // Roll right side down: a left -> right baseline's right end goes down.
  const Ned rolled = baseline_ned({0.0, -0.5, 0.0}, {0.0, 0.5, 0.0}, 0.0, 0.0, 10.0);
  EXPECT_NEAR(rolled.east_m, c10, 1e-12);
  EXPECT_NEAR(rolled.down_m, s10, 1e-12);
  // Roll does not move a fore-aft baseline; an antenna above the point moves with pitch.
  const Ned fore_aft = baseline_ned(base, rover, 0.0, 0.0, 30.0);
  EXPECT_NEAR(fore_aft.north_m, 1.0, 1e-12);
  EXPECT_NEAR(fore_aft.down_m, 0.0, 1e-12);
  const Enu mast = offset_enu({0.0, 0.0, -1.0}, 0.0, 10.0, 0.0);  // 1 m up, nose 10 degrees up
  EXPECT_NEAR(mast.north_m, -s10, 1e-12);  // leans back
  EXPECT_NEAR(mast.up_m, c10, 1e-12);

  RoverRelPos r(rover_options(), 3);  // 1.2 m fore-aft
  sources::Truth truth;
  truth.yaw_deg = 45.0;
  truth.tilt = {20.0, 5.0};
  const RelativePosition rel = r.at(kT0, truth, kT0);
  ASSERT_TRUE(rel.rel_pos_valid);
  ASSERT_TRUE(rel.heading_valid);
  EXPECT_NEAR(rel.down_m, -1.2 * std::sin(20.0 * M_PI / 180.0), 0.05);
  EXPECT_NEAR(rel.length_m, 1.2, 0.05);  // 3-D: the length of the baseline, whatever the tilt
  EXPECT_NEAR(std::hypot(rel.north_m, rel.east_m), 1.2 * std::cos(20.0 * M_PI / 180.0), 0.05);
  EXPECT_LT(std::abs(angle_diff_deg(rel.heading_deg, 45.0)), 4.0 * rel.acc_heading_deg);
}

}  // namespace moving_base_test
}  // namespace
}  // namespace gpsemu::heading
