// The mavlink: source over a scripted socket (tests/support/scripted_pose_socket.hpp): states into
// the pose history (position, velocity with its vertical part, attitude), the most complete
// message wins, one vehicle at a time, staleness, frames cut by a datagram or a dropped TCP
// connection, and the counts the summary prints.
#include <gtest/gtest.h>

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "emulator/sources/mavlink_source.hpp"
#include "tests/support/scripted_pose_socket.hpp"

namespace gpsemu::sources {
namespace {
namespace mavlink_source_test {

using namespace std::chrono_literals;
using Kind = transport::ReceivedMessage::Kind;
using mavlink::EncodeOptions;
using mavlink::VehicleState;

const UtcNs kT0 = UtcNs{std::chrono::seconds(1'700'000'000)};
UtcNs at_s(double s) { return kT0 + std::chrono::nanoseconds{std::llround(s * 1e9)}; }

const Geodetic kOrigin{43.0725, -89.4125, 260.0};

std::string text_of(const std::vector<std::uint8_t>& bytes) { return std::string(bytes.begin(), bytes.end()); }

class MavlinkSourceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sink_ = std::make_shared<test::RecordingSink>();
    previous_ = spdlog::default_logger();
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("test", sink_));
  }
  void TearDown() override {
    source_.reset();
    spdlog::set_default_logger(previous_);
  }
  void make(bool datagrams) {
    MavlinkSourceOptions o;
    o.history.timeout = 1s;
    o.datagrams = datagrams;
    source_ = std::make_unique<MavlinkPoseSource>(std::make_unique<test::FakeSocket>(&queue_), frame_, o);
  }
  /// A state at `east_m`, `north_m` of the origin, `up_m` above it, moving N/E/D.
  VehicleState state(std::uint32_t id, double east_m, double north_m, double up_m = 10.0) const {
    const Geodetic g = frame_.to_geodetic({east_m, north_m, up_m});
    VehicleState s;
    s.message_id = id;
    s.lat_deg = g.lat_deg;
    s.lon_deg = g.lon_deg;
    s.alt_msl_m = g.alt_m;
    s.velocity = mavlink::VelocityNed{2.0, 1.0, -0.5};
    s.yaw_deg = 30.0;
    s.pitch_deg = 4.0;
    s.roll_deg = -3.0;
    return s;
  }
  void send(double s, const std::string& bytes, std::uint64_t sender = 1, Kind kind = Kind::message) {
    queue_.push_back({kind, bytes, at_s(s), sender, "sim-" + std::to_string(sender)});
  }
  std::uint64_t dropped(PoseReject r) const { return source_->stats().rejected[static_cast<std::size_t>(r)]; }

  LocalFrame frame_{kOrigin};
  std::deque<test::Scripted> queue_;
  std::shared_ptr<test::RecordingSink> sink_;
  std::shared_ptr<spdlog::logger> previous_;
  std::unique_ptr<MavlinkPoseSource> source_;
};

TEST_F(MavlinkSourceTest, SimStateReachesTheTruthWithVerticalVelocityAndAttitude) {
  make(true);
  send(0.00, text_of(mavlink::encode_state(state(mavlink::kSimStateId, 10.0, 20.0))));
  send(0.10, text_of(mavlink::encode_state(state(mavlink::kSimStateId, 10.1, 20.2))));
  source_->service();
  const auto truth = source_->truth_at(at_s(0.05));
  ASSERT_TRUE(truth);
  EXPECT_NEAR(truth->position_m.east_m, 10.05, 0.02);  // lat_int/lon_int: 1e-7 degrees
  EXPECT_NEAR(truth->position_m.north_m, 20.1, 0.02);
  EXPECT_NEAR(truth->position_m.up_m, 10.0, 1e-3);
  EXPECT_NEAR(truth->velocity_mps.north_m, 2.0, 1e-6);
  EXPECT_NEAR(truth->velocity_mps.east_m, 1.0, 1e-6);
  EXPECT_NEAR(truth->velocity_mps.up_m, 0.5, 1e-6);  // vd -0.5: climbing
  EXPECT_NEAR(*truth->yaw_deg, 30.0, 1e-4);
  EXPECT_NEAR(truth->tilt.pitch_deg, 4.0, 1e-4);
  EXPECT_NEAR(truth->tilt.roll_deg, -3.0, 1e-4);
  EXPECT_EQ(source_->stats().accepted, 2u);
}

TEST_F(MavlinkSourceTest, SimstateWithoutAltitudeHoldsAtTheOriginsAltitudeAndSpeedComesFromTheTrack) {
  make(true);
  send(0.0, text_of(mavlink::encode_state(state(mavlink::kSimstateId, 0.0, 0.0))));
  send(0.5, text_of(mavlink::encode_state(state(mavlink::kSimstateId, 0.0, 1.0))));
  source_->service();
  const auto truth = source_->truth_at(at_s(0.5));
  ASSERT_TRUE(truth);
  EXPECT_NEAR(truth->position_m.up_m, 0.0, 1e-3);
  EXPECT_NEAR(truth->velocity_mps.north_m, 2.0, 0.05);  // 1 m in 0.5 s
}

TEST_F(MavlinkSourceTest, SimstateIsTimedByTheAttitudeBeforeItSoBunchedArrivalsKeepTheirSpeed) {
  // ArduPilot's EXTRA1 stream: ATTITUDE (time_boot_ms) then SIMSTATE, every 250 ms of autopilot
  // time; a bursty link delivers three pairs within 4 ms. The track speed is 0.5 m per 250 ms.
  make(true);
  const auto attitude = [](std::uint32_t time_boot_ms) {
    std::vector<std::uint8_t> p(28, 0);
    for (int i = 0; i < 4; ++i) p[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(time_boot_ms >> (8 * i));
    return text_of(mavlink::encode_frame(mavlink::kAttitudeId, p));
  };
  for (int k = 0; k < 3; ++k) {
    send(0.002 * k, attitude(1000 + 250 * static_cast<std::uint32_t>(k)) +
                        text_of(mavlink::encode_state(state(mavlink::kSimstateId, 0.0, 0.5 * k))));
  }
  source_->service();
  EXPECT_EQ(source_->stats().accepted, 3u);
  const auto truth = source_->truth_at(at_s(0.004));
  ASSERT_TRUE(truth);
  EXPECT_NEAR(truth->velocity_mps.north_m, 2.0, 0.05);
  EXPECT_NEAR(truth->velocity_mps.east_m, 0.0, 0.05);
}

TEST_F(MavlinkSourceTest, TheMostCompleteMessageWinsOverSimstate) {
  // ArduPilot sends SIMSTATE and SIM_STATE back to back: SIM_STATE is used, SIMSTATE superseded.
  make(true);
  for (int i = 0; i < 5; ++i) {
    send(0.1 * i, text_of(mavlink::encode_state(state(mavlink::kSimstateId, 0.0, 0.1 * i))));
    send(0.1 * i + 0.0001, text_of(mavlink::encode_state(state(mavlink::kSimStateId, 0.0, 0.1 * i))));
  }
  source_->service();
  EXPECT_EQ(source_->stats().accepted_by_message[0], 5u);  // SIM_STATE
  EXPECT_EQ(source_->stats().accepted_by_message[2], 1u);  // the first SIMSTATE, before SIM_STATE came
  EXPECT_EQ(source_->stats().superseded, 4u);
  EXPECT_EQ(dropped(PoseReject::flood), 0u);
}

TEST_F(MavlinkSourceTest, AnotherSystemIsDroppedUntilTheOwnerFallsSilent) {
  make(true);
  send(0.0, text_of(mavlink::encode_state(state(mavlink::kSimStateId, 0.0, 0.0), {.system_id = 1})));
  send(0.1, text_of(mavlink::encode_state(state(mavlink::kSimStateId, 500.0, 0.0), {.system_id = 2})));
  send(0.2, text_of(mavlink::encode_state(state(mavlink::kSimStateId, 0.0, 0.4), {.system_id = 1})));
  send(1.5, text_of(mavlink::encode_state(state(mavlink::kSimStateId, 500.0, 0.0), {.system_id = 2})));
  source_->service();
  EXPECT_EQ(dropped(PoseReject::other_sender), 1u);
  EXPECT_EQ(source_->stats().sender_changes, 1u);
  EXPECT_NEAR(source_->truth_at(at_s(1.5))->position_m.east_m, 500.0, 0.02);
  EXPECT_NE(sink_->text.find("MAVLink vehicle is now sim-1 system 2"), std::string::npos) << sink_->text;
}

TEST_F(MavlinkSourceTest, NoFixAfterTheTimeoutAndBackWhenStatesResume) {
  make(true);
  send(0.0, text_of(mavlink::encode_state(state(mavlink::kHilStateQuaternionId, 1.0, 1.0))));
  source_->service();
  EXPECT_TRUE(source_->truth_at(at_s(0.5)));
  EXPECT_FALSE(source_->truth_at(at_s(1.2)));
  send(2.0, text_of(mavlink::encode_state(state(mavlink::kHilStateQuaternionId, 1.0, 1.0))));
  source_->service();
  EXPECT_TRUE(source_->truth_at(at_s(2.0)));
  EXPECT_NE(sink_->text.find("no MAVLink state for"), std::string::npos) << sink_->text;
  EXPECT_NE(sink_->text.find("states resumed"), std::string::npos) << sink_->text;
}

TEST_F(MavlinkSourceTest, BadFramesAreCountedLoggedAndTheStreamGoesOn) {
  make(true);
  auto bad = mavlink::encode_state(state(mavlink::kSimStateId, 0.0, 0.0));
  bad.back() ^= 0xFF;
  send(0.00, text_of(mavlink::encode_state(state(mavlink::kSimStateId, 0.0, 0.0))));
  send(0.05, text_of(bad));
  send(0.10, "junk" + text_of(mavlink::encode_state(state(mavlink::kSimStateId, 0.0, 0.2))));
  VehicleState far = state(mavlink::kSimStateId, 0.0, 0.0);
  far.lat_deg = 95.0;
  send(0.15, text_of(mavlink::encode_state(far)));
  source_->service();
  EXPECT_EQ(source_->stats().accepted, 2u);
  EXPECT_EQ(source_->frames().bad_crc, 1u);
  EXPECT_EQ(source_->frames().garbage_bytes, 4u);
  EXPECT_EQ(dropped(PoseReject::out_of_range), 1u);
  EXPECT_NE(sink_->text.find("skipped 1 more MAVLink bad_crc (1 in all)"), std::string::npos) << sink_->text;
  const std::string summary = source_->counts_text();
  EXPECT_NE(summary.find("2 states used (SIM_STATE 2), 1 dropped, out_of_range 1"), std::string::npos) << summary;
  EXPECT_NE(summary.find("bad_crc 1, garbage_bytes 4"), std::string::npos) << summary;
}

TEST_F(MavlinkSourceTest, DatagramsTheKernelDroppedAreCountedApartFromStates) {
  make(true);
  send(0.00, text_of(mavlink::encode_state(state(mavlink::kSimStateId, 0.0, 0.0))));
  queue_.push_back({Kind::kernel_dropped, "", at_s(0.05), 0, "", 5});  // a heartbeat or a state: unknown
  send(0.10, text_of(mavlink::encode_state(state(mavlink::kSimStateId, 0.0, 0.1))));
  source_->service();
  EXPECT_EQ(source_->stats().accepted, 2u);
  EXPECT_EQ(source_->stats().datagrams_lost, 5u);
  EXPECT_EQ(dropped(PoseReject::kernel_overflow), 0u) << "not counted as states dropped";
  EXPECT_NE(sink_->text.find("the kernel dropped 5 datagram(s)"), std::string::npos) << sink_->text;
  const std::string summary = source_->counts_text();
  EXPECT_NE(summary.find("2 states used (SIM_STATE 2), 0 dropped"), std::string::npos) << summary;
  EXPECT_NE(summary.find("5 datagrams dropped by the kernel"), std::string::npos) << summary;
}

TEST_F(MavlinkSourceTest, TcpFramesSpanReadsAndADroppedConnectionCountsItsCutFrame) {
  make(false);
  const std::string a = text_of(mavlink::encode_state(state(mavlink::kSimStateId, 0.0, 0.0)));
  const std::string b = text_of(mavlink::encode_state(state(mavlink::kSimStateId, 0.0, 0.1)));
  send(0.00, "", 7, Kind::connected);
  send(0.00, a.substr(0, 30), 7);
  send(0.01, a.substr(30) + b.substr(0, 50), 7);
  send(0.10, b.substr(50) + b.substr(0, 20), 7);  // then the connection drops mid-frame
  send(0.20, "", 7, Kind::disconnected);
  source_->service();
  EXPECT_EQ(source_->stats().accepted, 2u);
  EXPECT_EQ(source_->frames().partial_frame, 1u);
  EXPECT_EQ(source_->stats().connections, 1u);
  EXPECT_EQ(source_->stats().disconnections, 1u);
}

TEST_F(MavlinkSourceTest, AStreamWithoutStatesSaysWhichMessagesToSend) {
  make(true);
  const std::string heartbeat = text_of(mavlink::encode_frame(0, std::vector<std::uint8_t>(9, 1)));
  for (int i = 0; i < 500; ++i) send(0.001 * i, heartbeat);
  source_->service();
  source_->service();
  EXPECT_EQ(source_->frames().unknown_message, 500u);
  EXPECT_NE(sink_->text.find("none of SIM_STATE, HIL_STATE_QUATERNION or SIMSTATE"), std::string::npos) << sink_->text;
}

}  // namespace mavlink_source_test
}  // namespace
}  // namespace gpsemu::sources
