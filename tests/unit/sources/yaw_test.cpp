// The vehicle's heading (yaw_deg) from every pose source: the simulator's trajectories face their
// direction of travel, a socket pose's yaw_deg is decoded, checked and wrapped, the pose history
// and a replayed trajectory interpolate it the shorter way round (across north too).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <sstream>
#include <variant>

#include "emulator/sources/pose_history.hpp"
#include "emulator/sources/pose_message.hpp"
#include "emulator/sources/sim.hpp"
#include "emulator/sources/trajectory_source.hpp"

namespace gpsemu::sources {
namespace {
namespace yaw_test {

using namespace std::chrono_literals;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");
const LocalFrame kFrame(Geodetic{43.0725, -89.4125, 260.0});

double yaw_at(PoseSource& s, UtcNs t) {
  const auto truth = s.truth_at(t);
  EXPECT_TRUE(truth && truth->yaw_deg);
  return truth && truth->yaw_deg ? *truth->yaw_deg : -1.0;
}

TEST(Yaw, SimulatorFacesItsDirectionOfTravel) {
  SimOptions o;
  o.radius_m = 20.0;
  o.speed_mps = 2.0;  // 0.1 rad/s: a quarter turn in 15.7 s
  auto circle = make_sim_source("circle", o, kFrame, kT0);
  EXPECT_NEAR(yaw_at(*circle, kT0), 90.0, 1e-9);  // the southern point, heading east
  const double quarter_s = (M_PI / 2.0) / 0.1;
  // the eastern point: facing north (359.9999... or 0)
  EXPECT_NEAR(std::remainder(yaw_at(*circle, kT0 + std::chrono::nanoseconds(std::llround(quarter_s * 1e9))), 360.0), 0.0, 1e-6);
  EXPECT_NEAR(yaw_at(*circle, kT0 + std::chrono::nanoseconds(std::llround(2 * quarter_s * 1e9))), 270.0, 1e-6);

  o.heading_deg = 135.0;
  auto line = make_sim_source("line", o, kFrame, kT0);
  EXPECT_NEAR(yaw_at(*line, kT0 + 5s), 135.0, 1e-9);
  EXPECT_NEAR(yaw_at(*line, kT0 + 500s), 135.0, 1e-9);  // stopped: still facing its way
  auto still = make_sim_source("stationary", o, kFrame, kT0);
  EXPECT_NEAR(yaw_at(*still, kT0), 135.0, 1e-9);
}

TEST(Yaw, PoseMessageYawIsCheckedAndWrapped) {
  const auto yaw_of = [](const char* json) { return std::get<PoseMessage>(decode_pose(json)).yaw_deg; };
  EXPECT_EQ(yaw_of(R"({"x": 1, "y": 2, "yaw_deg": 45.5})"), 45.5);
  EXPECT_EQ(yaw_of(R"({"x": 1, "y": 2, "yaw_deg": -90})"), 270.0);
  EXPECT_EQ(yaw_of(R"({"x": 1, "y": 2, "yaw_deg": 360})"), 0.0);
  EXPECT_FALSE(yaw_of(R"({"x": 1, "y": 2})").has_value());
  EXPECT_EQ(std::get<PoseReject>(decode_pose(R"({"x": 1, "y": 2, "yaw_deg": 361})")), PoseReject::out_of_range);
  EXPECT_EQ(std::get<PoseReject>(decode_pose(R"({"x": 1, "y": 2, "yaw_deg": "N"})")), PoseReject::not_a_number);
  EXPECT_EQ(std::get<PoseReject>(decode_pose(R"({"x": 1, "y": 2, "yaw": 3})")), PoseReject::extra_key);
}

TEST(Yaw, HistoryInterpolatesTheShorterWayAndHoldsAfterTheNewest) {
  PoseHistory h;
  ASSERT_EQ(h.push(TimedPose{kT0, std::nullopt, {0, 0, 0}, std::nullopt, 350.0, {}}), PushResult::accepted);
  ASSERT_EQ(h.push(TimedPose{kT0 + 100ms, std::nullopt, {0, 1, 0}, std::nullopt, 10.0, {}}), PushResult::accepted);
  EXPECT_NEAR(*h.sample(kT0 + 25ms)->yaw_deg, 355.0, 1e-9);
  EXPECT_NEAR(*h.sample(kT0 + 75ms)->yaw_deg, 5.0, 1e-9);
  EXPECT_NEAR(*h.sample(kT0 + 150ms)->yaw_deg, 10.0, 1e-9);
  PoseHistory without;
  ASSERT_EQ(without.push(TimedPose{kT0, std::nullopt, {0, 0, 0}, std::nullopt, std::nullopt, {}}), PushResult::accepted);
  EXPECT_FALSE(without.sample(kT0)->yaw_deg.has_value());
}

TEST(Yaw, ReplayedTrajectoryCarriesItsYawColumn) {
  std::istringstream csv("time_s,east_m,north_m,yaw_deg\n0,0,0,-10\n1,0,1,20\n");
  TrajectorySource s(read_trajectory_csv(csv, "drive.csv", kFrame, kT0));
  EXPECT_NEAR(yaw_at(s, kT0), 350.0, 1e-9);
  EXPECT_NEAR(yaw_at(s, kT0 + 500ms), 5.0, 1e-9);
  std::istringstream bad("time_s,east_m,north_m,yaw_deg\n0,0,0,400\n1,0,1,20\n");
  try {
    (void)read_trajectory_csv(bad, "drive.csv", kFrame, kT0);
    ADD_FAILURE() << "a yaw of 400 degrees was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("drive.csv:2: column yaw_deg"), std::string::npos) << e.what();
  }
}

// Pitch and roll (docs/heading.md): optional beside yaw_deg, 0 when absent, checked, interpolated.
TEST(Tilt, PoseMessagePitchAndRollAreOptionalAndChecked) {
  const auto msg = [](const char* json) { return std::get<PoseMessage>(decode_pose(json)); };
  const PoseMessage m = msg(R"({"x": 1, "y": 2, "yaw_deg": 10, "pitch_deg": 5.5, "roll_deg": -20})");
  EXPECT_EQ(m.pitch_deg, 5.5);
  EXPECT_EQ(m.roll_deg, -20.0);
  EXPECT_EQ(msg(R"({"x": 1, "y": 2})").pitch_deg, 0.0);
  EXPECT_EQ(std::get<PoseReject>(decode_pose(R"({"x": 1, "y": 2, "pitch_deg": 91})")), PoseReject::out_of_range);
  EXPECT_EQ(std::get<PoseReject>(decode_pose(R"({"x": 1, "y": 2, "roll_deg": -181})")), PoseReject::out_of_range);
  EXPECT_EQ(std::get<PoseReject>(decode_pose(R"({"x": 1, "y": 2, "pitch": 3})")), PoseReject::extra_key);
}

TEST(Tilt, HistoryAndTrajectoryInterpolateIt) {
  PoseHistory h;
  ASSERT_EQ(h.push(TimedPose{kT0, std::nullopt, {0, 0, 0}, std::nullopt, 0.0, {0.0, 10.0}}), PushResult::accepted);
  ASSERT_EQ(h.push(TimedPose{kT0 + 100ms, std::nullopt, {0, 1, 0}, std::nullopt, 0.0, {4.0, -10.0}}), PushResult::accepted);
  EXPECT_NEAR(h.sample(kT0 + 25ms)->tilt.pitch_deg, 1.0, 1e-9);
  EXPECT_NEAR(h.sample(kT0 + 25ms)->tilt.roll_deg, 5.0, 1e-9);
  EXPECT_NEAR(h.sample(kT0 + 150ms)->tilt.pitch_deg, 4.0, 1e-9);  // held after the newest
  std::istringstream csv("time_s,east_m,north_m,yaw_deg,pitch_deg,roll_deg\n0,0,0,0,2,0\n1,0,1,0,4,-6\n");
  TrajectorySource s(read_trajectory_csv(csv, "drive.csv", kFrame, kT0));
  EXPECT_NEAR(s.truth_at(kT0 + 500ms)->tilt.pitch_deg, 3.0, 1e-9);
  EXPECT_NEAR(s.truth_at(kT0 + 500ms)->tilt.roll_deg, -3.0, 1e-9);
  std::istringstream bad("time_s,east_m,north_m,pitch_deg\n0,0,0,95\n1,0,1,0\n");
  EXPECT_THROW((void)read_trajectory_csv(bad, "drive.csv", kFrame, kT0), std::runtime_error);
}

}  // namespace yaw_test
}  // namespace
}  // namespace gpsemu::sources
