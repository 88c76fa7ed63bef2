// Decoding the truth of SIM_STATE, HIL_STATE_QUATERNION and SIMSTATE (vehicle_state.hpp): the
// attitude from a quaternion and from Euler angles, ArduPilot's degE7 in SIM_STATE's float
// fields, and the values a JSON pose would be refused for refused here by the same reasons.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "emulator/sources/mavlink/vehicle_state.hpp"

namespace gpsemu::sources::mavlink {
namespace {
namespace mavlink_state_test {

/// The one frame `bytes` holds.
Frame frame_of(const std::vector<std::uint8_t>& bytes) {
  FrameReader reader;
  reader.feed(bytes);
  auto f = reader.next();
  EXPECT_TRUE(f);
  return f.value_or(Frame{});
}

VehicleState level(std::uint32_t id) {
  VehicleState s;
  s.message_id = id;
  s.lat_deg = 52.5163;
  s.lon_deg = 13.3777;
  s.alt_msl_m = 34.0;
  s.velocity = VelocityNed{0.0, 0.0, 0.0};
  return s;
}

/// A SIM_STATE payload (92 bytes) with float fields set at byte offsets.
std::vector<std::uint8_t> sim_state_payload(std::initializer_list<std::pair<std::size_t, float>> fields) {
  std::vector<std::uint8_t> p(92, 0);
  for (const auto& [at, v] : fields) {
    const auto u = std::bit_cast<std::uint32_t>(v);
    for (int i = 0; i < 4; ++i) p[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(u >> (8 * i));
  }
  return p;
}

TEST(MavlinkState, QuaternionAndEulerAnglesAgree) {
  for (const Euler e : {Euler{0, 0, 0}, Euler{10, -20, 30}, Euler{-170, 80, 359}, Euler{45, 0, 180}}) {
    const auto q = quaternion_of_euler(e);
    const Euler back = euler_of_quaternion(q[0], q[1], q[2], q[3]);
    EXPECT_NEAR(back.roll_deg, e.roll_deg, 1e-9);
    EXPECT_NEAR(back.pitch_deg, e.pitch_deg, 1e-9);
    EXPECT_NEAR(back.yaw_deg, std::fmod(e.yaw_deg, 360.0), 1e-9);
  }
}

TEST(MavlinkState, SimStateWithoutAUnitQuaternionUsesItsEulerAngles) {
  // q all zero (a sender filling only the Euler fields): roll 0.1, pitch 0.2, yaw -0.5 rad.
  const auto p = sim_state_payload({{16, 0.1f}, {20, 0.2f}, {24, -0.5f}, {52, 52.5f}, {56, 13.4f}, {60, 34.0f}});
  const auto s = std::get<VehicleState>(decode_state(frame_of(encode_frame(kSimStateId, p))));
  EXPECT_NEAR(s.roll_deg, 5.729578, 1e-5);
  EXPECT_NEAR(s.pitch_deg, 11.459156, 1e-5);
  EXPECT_NEAR(s.yaw_deg, 360.0 - 28.647890, 1e-5);
  EXPECT_NEAR(s.lat_deg, 52.5, 1e-5);
}

TEST(MavlinkState, ArduPilotsDegE7InTheFloatFieldsIsReadAsDegE7) {
  // ArduPilot's SITL puts latitude * 1e7 into SIM_STATE's float lat/lon; a MAVLink 1 frame has no lat_int.
  const auto p = sim_state_payload({{0, 1.0f}, {52, 525163000.0f}, {56, 133777000.0f}, {60, 34.0f}});
  const auto s = std::get<VehicleState>(decode_state(frame_of(encode_frame(kSimStateId, p, {.version = 1}))));
  EXPECT_NEAR(s.lat_deg, 52.5163, 1e-5);
  EXPECT_NEAR(s.lon_deg, 13.3777, 1e-5);
}

TEST(MavlinkState, OneFloatFieldBeyondItsRangeIsRefusedNotReadAsDegE7) {
  // lat 400 beside a valid lon 13.4, no integer fields: once read as 0.00004, 0.0000013 (a fix
  // 8 710 km from the origin), refused now; so is the mirror case.
  for (const auto& [lat, lon] : {std::pair{400.0f, 13.4f}, std::pair{52.5f, 1800.0f}}) {
    const auto p = sim_state_payload({{0, 1.0f}, {52, lat}, {56, lon}, {60, 34.0f}});
    const auto r = decode_state(frame_of(encode_frame(kSimStateId, p, {.version = 1})));
    ASSERT_TRUE(std::holds_alternative<PoseReject>(r)) << lat << " " << lon;
    EXPECT_EQ(std::get<PoseReject>(r), PoseReject::out_of_range);
  }
}

TEST(MavlinkState, ValuesAJsonPoseWouldBeRefusedForAreRefusedByTheSameReason) {
  const auto reason = [](const VehicleState& s) {
    const auto r = decode_state(frame_of(encode_state(s)));
    return std::holds_alternative<PoseReject>(r) ? std::get<PoseReject>(r) : PoseReject::too_large;
  };
  VehicleState s = level(kSimStateId);
  s.alt_msl_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(reason(s), PoseReject::not_finite);
  s = level(kSimStateId);
  s.alt_msl_m = 2.0e6;
  EXPECT_EQ(reason(s), PoseReject::out_of_range);
  s = level(kSimStateId);
  s.velocity = VelocityNed{2.0e4, 0.0, 0.0};
  EXPECT_EQ(reason(s), PoseReject::out_of_range);
  s = level(kHilStateQuaternionId);
  s.lat_deg = 0.0;
  s.lon_deg = 0.0;
  EXPECT_EQ(reason(s), PoseReject::missing_key);  // a simulator without a position yet
  EXPECT_TRUE(std::holds_alternative<VehicleState>(decode_state(frame_of(encode_state(level(kSimstateId))))));
}

TEST(MavlinkState, HilStateQuaternionCarriesItsTimeStampAndCentimetreVelocities) {
  VehicleState s = level(kHilStateQuaternionId);
  s.time_usec = 1'700'000'000'123'456;
  s.velocity = VelocityNed{-1.23, 4.56, 0.07};
  const auto d = std::get<VehicleState>(decode_state(frame_of(encode_state(s))));
  EXPECT_EQ(d.time_usec, 1'700'000'000'123'456u);
  EXPECT_DOUBLE_EQ(d.velocity->north_mps, -1.23);
  EXPECT_DOUBLE_EQ(d.velocity->east_mps, 4.56);
  EXPECT_DOUBLE_EQ(d.velocity->down_mps, 0.07);
  EXPECT_DOUBLE_EQ(*d.alt_msl_m, 34.0);
}

}  // namespace mavlink_state_test
}  // namespace
}  // namespace gpsemu::sources::mavlink
