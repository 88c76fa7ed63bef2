// The built-in simulator scenarios and the receiver model on top of them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "emulator/model/receiver.hpp"
#include "emulator/sources/sim.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace receiver_sim_test {

using namespace std::chrono;
using sources::SimOptions;

const UtcNs kStart = parse_iso8601_utc("2024-05-01T12:00:00Z");
const LocalFrame kFrame({43.0725, -89.4125, 260.0});

std::unique_ptr<noise::NoiseModel> no_noise() {
  noise::NoiseConfig c;
  c.model = noise::Model::none;
  return noise::make_noise_model(c, 1);
}

/// A receiver without noise: the position's and the velocity's errors off (--noise none).
ReceiverOptions exact() {
  ReceiverOptions o;
  o.velocity.white_sigma_mps = o.velocity.wander_sigma_mps = 0.0;
  return o;
}

TEST(Sim, StationaryStaysAtTheOriginWithZeroSpeed) {
  auto src = sources::make_sim_source("stationary", {}, kFrame, kStart);
  Receiver rx(kFrame, exact(), no_noise(), kStart);
  const auto fix = rx.fix_at(kStart + seconds(30), src->truth_at(kStart + seconds(30)));
  ASSERT_TRUE(fix.has_fix());
  EXPECT_NEAR(fix.lat_deg, 43.0725, 1e-9);
  EXPECT_NEAR(fix.lon_deg, -89.4125, 1e-9);
  EXPECT_NEAR(fix.alt_msl_m, 260.0, 1e-6);
  EXPECT_EQ(fix.speed_mps, 0.0);
  EXPECT_FALSE(fix.course_deg_true.has_value());
}

// A copter climbing in place (2 m/s up, no horizontal motion) under a static hold (5 m radius):
// its altitude and vertical velocity follow the climb; the hold is for a receiver standing still.
TEST(Sim, StaticHoldDoesNotFreezeAClimbInPlace) {
  ReceiverOptions o = exact();
  o.hold.radius_m = 5.0;
  Receiver rx(kFrame, o, no_noise(), kStart);
  for (int s = 0; s <= 10; ++s) {
    sources::Truth climbing;
    climbing.position_m = {0.0, 0.0, 2.0 * s};
    climbing.velocity_mps = {0.0, 0.0, 2.0};
    const auto fix = rx.fix_at(kStart + seconds(s), climbing);
    ASSERT_TRUE(fix.has_fix());
    EXPECT_NEAR(fix.alt_msl_m, 260.0 + 2.0 * s, 1e-6) << s;
    EXPECT_EQ(fix.vel_up_mps, 2.0);
  }
}

TEST(Sim, LineDrivesStraightAtItsSpeedThenStops) {
  SimOptions o;
  o.speed_mps = 2.0;
  o.heading_deg = 90.0;
  o.drive_time_s = 20.0;
  auto src = sources::make_sim_source("line", o, kFrame, kStart);
  for (int s = 0; s <= 20; ++s) {
    const auto truth = src->truth_at(kStart + seconds(s));
    ASSERT_TRUE(truth);
    EXPECT_NEAR(truth->position_m.east_m, 2.0 * s, 1e-9);
    EXPECT_NEAR(truth->position_m.north_m, 0.0, 1e-9);
  }
  EXPECT_NEAR(src->truth_at(kStart + seconds(10))->velocity_mps.east_m, 2.0, 1e-12);
  const auto after = src->truth_at(kStart + seconds(60));
  EXPECT_NEAR(after->position_m.east_m, 40.0, 1e-9);
  EXPECT_EQ(after->velocity_mps.east_m, 0.0);
}

TEST(Sim, ReceiverReportsTheLinesCourseAndHoldsItWhenStopped) {
  SimOptions o;
  o.heading_deg = 30.0;
  auto src = sources::make_sim_source("line", o, kFrame, kStart);
  ReceiverOptions holding = exact();
  holding.course_at_rest = CourseAtRest::held;  // as SiRF and SkyTraq (a u-blox leaves it empty)
  Receiver rx(kFrame, holding, no_noise(), kStart);
  const auto moving = rx.fix_at(kStart + seconds(5), src->truth_at(kStart + seconds(5)));
  ASSERT_TRUE(moving.course_deg_true);
  EXPECT_NEAR(*moving.course_deg_true, 30.0, 1e-9);
  EXPECT_NEAR(moving.speed_mps, 2.0, 1e-12);
  const auto stopped = rx.fix_at(kStart + seconds(40), src->truth_at(kStart + seconds(40)));
  EXPECT_EQ(stopped.speed_mps, 0.0);
  EXPECT_NEAR(*stopped.course_deg_true, 30.0, 1e-9);
}

TEST(Sim, CircleKeepsItsRadiusAndTangentialVelocity) {
  SimOptions o;
  o.radius_m = 20.0;
  o.speed_mps = 4.0;
  auto src = sources::make_sim_source("circle", o, kFrame, kStart);
  for (int s = 0; s < 60; s += 3) {
    const auto t = src->truth_at(kStart + seconds(s));
    EXPECT_NEAR(std::hypot(t->position_m.east_m, t->position_m.north_m), 20.0, 1e-9);
    EXPECT_NEAR(std::hypot(t->velocity_mps.east_m, t->velocity_mps.north_m), 4.0, 1e-9);
    EXPECT_NEAR(t->position_m.east_m * t->velocity_mps.east_m + t->position_m.north_m * t->velocity_mps.north_m,
                0.0, 1e-9);
  }
}

TEST(Sim, NoTruthMeansNoFix) {
  Receiver rx(kFrame, {}, no_noise(), kStart);
  const auto fix = rx.fix_at(kStart, std::nullopt);
  EXPECT_FALSE(fix.has_fix());
  EXPECT_EQ(fix.time_utc, floor<milliseconds>(kStart));
}

std::string write_csv(const std::string& name, const std::string& text) {
  const auto path = test::scratch_root() / ("gpsemu_wp_" + std::to_string(::getpid()) + name);
  std::ofstream(path) << text;
  return path.string();
}

TEST(Waypoints, DrivesEachLegAtItsSpeed) {
  const auto file = write_csv("a.csv", "# a square\neast_m,north_m,speed_mps\n0,0,2\n10,0,5\n10,10,\n");
  auto src = sources::make_sim_source("waypoints:" + file, {}, kFrame, kStart);
  EXPECT_NEAR(src->truth_at(kStart + seconds(5))->position_m.east_m, 10.0, 1e-9);  // 10 m at 2 m/s
  const auto t6 = src->truth_at(kStart + seconds(6));
  EXPECT_NEAR(t6->position_m.north_m, 5.0, 1e-9);                                    // then 5 m/s north
  EXPECT_NEAR(t6->velocity_mps.north_m, 5.0, 1e-9);
  const auto end = src->truth_at(kStart + seconds(100));
  EXPECT_NEAR(end->position_m.north_m, 10.0, 1e-9);
  EXPECT_EQ(end->velocity_mps.north_m, 0.0);
}

TEST(Waypoints, GeodeticColumnsAreConvertedAboutTheOrigin) {
  const auto file = write_csv("b.csv", "lat_deg,lon_deg\n43.0725,-89.4125\n43.0734,-89.4125\n");
  auto src = sources::make_sim_source("waypoints:" + file, {}, kFrame, kStart);
  EXPECT_NEAR(src->truth_at(kStart + seconds(500))->position_m.north_m, 100.0, 0.5);
}

TEST(Waypoints, ErrorsNameTheFileAndLine) {
  const auto bad = write_csv("c.csv", "east_m,north_m\n0,0\n1,x\n");
  try {
    (void)sources::make_sim_source("waypoints:" + bad, {}, kFrame, kStart);
    FAIL() << "accepted a bad waypoint file";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find(bad + ":3"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)sources::make_sim_source("waypoints:/nonexistent.csv", {}, kFrame, kStart), std::runtime_error);
  EXPECT_THROW((void)sources::make_sim_source("spiral", {}, kFrame, kStart), std::invalid_argument);
}

// Found while writing waypoints_csv_fuzz: an empty required cell was dereferenced as a number
// (undefined behaviour), and values beyond any real route produced infinite positions.
TEST(Waypoints, BadValuesAreRefusedNamingLineAndColumn) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"lat_deg,lon_deg\n43,-89\n,-89\n", "w.csv:3: column lat_deg is empty"},
      {"east_m,north_m\n1,\n", "w.csv:2: column north_m is empty"},
      {"east_m,north_m,east_m\n1,2,3\n", "w.csv:1: column 'east_m' appears twice in the header"},
      {"lat_deg,lon_deg\n43,-189\n", "w.csv:2: longitude -189 outside [-180, 180]"},
      {"lat_deg,lon_deg,alt_m\n43,-89,1e300\n", "w.csv:2: alt_m 1e+300 outside [-10000, 1e+06] metres"},
      {"east_m,north_m\n1e300,-1e300\n", "w.csv:2: east_m 1e+300 is outside +-1e+07 metres"},
      {"east_m,north_m,up_m\n1,2,-2e7\n", "w.csv:2: up_m -20000000 is outside +-1e+07 metres"},
      {"east_m,north_m,speed_mps\n1,2,1e5\n", "w.csv:2: speed_mps must be > 0 and <= 10000"},
      {"east_m,north_m,speed_mps\n1,2,0\n", "w.csv:2: speed_mps must be > 0 and <= 10000"},
      {"# only a header\neast_m,north_m\n", "waypoint file 'w.csv' has no waypoints"},
  };
  for (const auto& [text, message] : cases) {
    std::istringstream in(text);
    try {
      (void)sources::read_waypoints(in, "w.csv", kFrame, 2.0);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), message);
    }
  }
  std::istringstream good("lat_deg,lon_deg,alt_m\n43.0725,-89.4125,\n");
  const auto points = sources::read_waypoints(good, "w.csv", kFrame, 2.0);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_NEAR(points[0].position_m.up_m, 0.0, 1e-6);  // an empty alt_m is the origin's
  EXPECT_EQ(points[0].speed_mps, 2.0);
}

}  // namespace receiver_sim_test
}  // namespace
}  // namespace gpsemu
