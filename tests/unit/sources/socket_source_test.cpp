// The udp:/tcp: source over a scripted fake socket: decoding into the history, drops counted per
// reason, one sender at a time (take-over after the owner's silence or disconnect), the bound on
// work per service() call, and what the log says (a recording spdlog sink).
#include <gtest/gtest.h>

#include <deque>
#include <memory>
#include <mutex>
#include <string>

#include <fmt/format.h>
#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include "emulator/sources/socket_source.hpp"
#include "tests/support/scripted_pose_socket.hpp"

namespace gpsemu::sources {
namespace {
namespace socket_source_test {

using namespace std::chrono_literals;
using Kind = transport::ReceivedMessage::Kind;
using test::FakeSocket;
using test::RecordingSink;
using test::Scripted;

const UtcNs kT0 = UtcNs{std::chrono::seconds(1'700'000'000)};
UtcNs at_s(double s) { return kT0 + std::chrono::nanoseconds{std::llround(s * 1e9)}; }

class SocketSourceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sink_ = std::make_shared<RecordingSink>();
    previous_ = spdlog::default_logger();
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("test", sink_));
    source_ = std::make_unique<SocketPoseSource>(std::make_unique<FakeSocket>(&queue_), frame_, options());
  }
  void TearDown() override {
    source_.reset();
    spdlog::set_default_logger(previous_);
  }
  static SocketSourceOptions options() {
    SocketSourceOptions o;
    o.history.timeout = 1s;
    o.max_messages_per_service = 256;
    return o;
  }
  void send(double s, const std::string& bytes, std::uint64_t sender = 1, Kind kind = Kind::message) {
    queue_.push_back({kind, bytes, at_s(s), sender, "sender-" + std::to_string(sender)});
  }
  std::uint64_t dropped(PoseReject r) const { return source_->stats().rejected[static_cast<std::size_t>(r)]; }

  LocalFrame frame_{Geodetic{43.0725, -89.4125, 260.0}};
  std::deque<Scripted> queue_;
  std::shared_ptr<RecordingSink> sink_;
  std::shared_ptr<spdlog::logger> previous_;
  std::unique_ptr<SocketPoseSource> source_;
};

TEST_F(SocketSourceTest, LocalAndGeodeticPosesReachTheTruth) {
  send(0.00, R"({"x": 10, "y": 20, "z": 1})");
  source_->service();
  auto truth = source_->truth_at(at_s(0.0));
  ASSERT_TRUE(truth);
  EXPECT_NEAR(truth->position_m.east_m, 10.0, 1e-9);
  EXPECT_NEAR(truth->position_m.north_m, 20.0, 1e-9);
  send(0.02, R"({"lat": 43.0725, "lon": -89.4125})");  // the origin, at the origin's altitude
  source_->service();
  truth = source_->truth_at(at_s(0.02));
  ASSERT_TRUE(truth);
  EXPECT_NEAR(truth->position_m.east_m, 0.0, 1e-6);
  EXPECT_NEAR(truth->position_m.up_m, 0.0, 1e-6);
  EXPECT_EQ(source_->stats().accepted, 2u);
}

TEST_F(SocketSourceTest, PosesReadLateInABurstHoldWhereTheirOwnTimesPutThem) {
  // 1 m/s east at 50 Hz, each pose read 1 ms after it was sent, then five read together 100 ms late
  // (gpsemu descheduled; TCP lines are stamped when read). Epoch 0.200 is sampled after the burst.
  for (int i = 0; i < 10; ++i) send(0.02 * i + 0.001, fmt::format(R"({{"t": {}, "x": {}, "y": 0}})", 0.02 * i, 0.02 * i));
  for (int i = 10; i < 15; ++i) send(0.300, fmt::format(R"({{"t": {}, "x": {}, "y": 0}})", 0.02 * i, 0.02 * i));
  source_->service();
  const auto truth = source_->truth_at(at_s(0.201));
  ASSERT_TRUE(truth);
  // Where the sender was at 0.200; by arrival times alone it would be 0.18 m (pose 9 to pose 10 at 0.300).
  EXPECT_NEAR(truth->position_m.east_m, 0.200, 1e-6);
  EXPECT_EQ(source_->stats().accepted, 15u);
}

TEST_F(SocketSourceTest, YawReachesTheTruthInterpolatedAcrossNorth) {
  send(0.00, R"({"x": 0, "y": 0, "yaw_deg": 350})");
  send(0.10, R"({"x": 0, "y": 1, "yaw_deg": -10})");   // 350 again: wrapped
  send(0.20, R"({"x": 0, "y": 2, "yaw_deg": 30})");
  send(0.30, R"({"x": 0, "y": 3, "yaw_deg": 400})");   // refused: the yaw stays 30
  source_->service();
  EXPECT_NEAR(*source_->truth_at(at_s(0.05))->yaw_deg, 350.0, 1e-9);
  EXPECT_NEAR(*source_->truth_at(at_s(0.15))->yaw_deg, 10.0, 1e-9);  // 350 -> 30 through north
  EXPECT_NEAR(*source_->truth_at(at_s(0.35))->yaw_deg, 30.0, 1e-9);
  EXPECT_EQ(dropped(PoseReject::out_of_range), 1u);
}

TEST_F(SocketSourceTest, BadInputIsCountedPerReasonAndTheLastGoodPoseStays) {
  send(0.00, R"({"x": 1, "y": 2})");
  send(0.01, "not json");
  send(0.02, R"({"x": NaN, "y": 2})");
  send(0.03, R"({"lat": 91, "lon": 0})");
  send(0.04, R"({"x": 1})");
  send(0.05, R"({"x": 1, "y": 2, "w": 3})");
  send(0.06, "", 1, Kind::too_large);
  send(0.07, "", 1, Kind::partial_line);
  send(0.08, "not json either");
  source_->service();
  EXPECT_EQ(dropped(PoseReject::not_json), 2u);
  EXPECT_EQ(dropped(PoseReject::not_finite), 1u);
  EXPECT_EQ(dropped(PoseReject::out_of_range), 1u);
  EXPECT_EQ(dropped(PoseReject::missing_key), 1u);
  EXPECT_EQ(dropped(PoseReject::extra_key), 1u);
  EXPECT_EQ(dropped(PoseReject::too_large), 1u);
  EXPECT_EQ(dropped(PoseReject::partial_line), 1u);
  const auto truth = source_->truth_at(at_s(0.5));
  ASSERT_TRUE(truth);
  EXPECT_NEAR(truth->position_m.east_m, 1.0, 1e-9);
  // Logged once per reason within the second: the second not_json is counted, not logged.
  EXPECT_NE(sink_->text.find("not_json (1 in all): 'not json'"), std::string::npos) << sink_->text;
  EXPECT_EQ(sink_->text.find("not json either"), std::string::npos) << sink_->text;
  send(1.5, "third bad one");
  source_->service();
  EXPECT_NE(sink_->text.find("dropped 2 messages from sender-1: not_json (3 in all)"), std::string::npos)
      << sink_->text;
}

TEST_F(SocketSourceTest, AnEpochBeforeTheFirstPoseHeldIsLoggedAsNoneYetNotANegativeSilence) {
  // The first pose holds at 2.03 s; epoch 2.00 comes after the source had one (it was fresh at 1.0
  // from an earlier sender's pose), then the history restarts ahead of the epoch.
  send(0.0, R"({"t": 100.0, "x": 1, "y": 2})");
  source_->service();
  EXPECT_TRUE(source_->truth_at(at_s(0.0)));
  send(2.03, R"({"t": 0.5, "x": 1, "y": 2})");  // t went back 99.5 s: a restarted simulator
  source_->service();
  EXPECT_FALSE(source_->truth_at(at_s(2.0)));
  EXPECT_NE(sink_->text.find("no pose yet at epoch"), std::string::npos) << sink_->text;
  EXPECT_NE(sink_->text.find("begin 0.03 s after it"), std::string::npos) << sink_->text;
  EXPECT_EQ(sink_->text.find(" -0."), std::string::npos) << sink_->text;
}

TEST_F(SocketSourceTest, StaleAfterTheTimeoutAndBackWhenPosesResumeLoggedOnceEach) {
  send(0.0, R"({"x": 1, "y": 2})");
  source_->service();
  EXPECT_TRUE(source_->truth_at(at_s(0.5)));
  EXPECT_FALSE(source_->truth_at(at_s(1.1)));
  EXPECT_FALSE(source_->truth_at(at_s(1.2)));
  send(3.0, R"({"x": 5, "y": 2})");
  source_->service();
  EXPECT_TRUE(source_->truth_at(at_s(3.0)));
  EXPECT_TRUE(source_->truth_at(at_s(3.1)));
  const auto count = [&](const std::string& needle) {
    std::size_t n = 0;
    for (auto at = sink_->text.find(needle); at != std::string::npos; at = sink_->text.find(needle, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("reporting no fix"), 1u) << sink_->text;
  EXPECT_EQ(count("poses resumed"), 1u) << sink_->text;
}

TEST_F(SocketSourceTest, OneSenderAtATimeAndTakeOverAfterTheOwnersSilence) {
  send(0.00, R"({"x": 1, "y": 0})", 1);
  send(0.01, R"({"x": 99, "y": 0})", 2);  // refused: sender 1 owns the stream
  send(0.50, R"({"x": 1, "y": 0})", 1);
  send(1.20, R"({"x": 99, "y": 0})", 2);  // sender 1 silent for 0.7 s: still refused
  send(1.60, R"({"x": 42, "y": 0})", 2);  // 1.1 s of silence: sender 2 takes over
  source_->service();
  EXPECT_EQ(dropped(PoseReject::other_sender), 2u);
  EXPECT_EQ(source_->stats().sender_changes, 1u);
  const auto truth = source_->truth_at(at_s(1.6));
  ASSERT_TRUE(truth);
  EXPECT_NEAR(truth->position_m.east_m, 42.0, 1e-9);
  EXPECT_FALSE(source_->truth_at(at_s(1.59))) << "the old sender's history is gone";
  EXPECT_NE(sink_->text.find("pose sender is now sender-2 (was sender-1)"), std::string::npos) << sink_->text;
}

TEST_F(SocketSourceTest, ADisconnectedTcpOwnerHandsOverAtOnce) {
  send(0.00, R"({"x": 1, "y": 0})", 7);
  send(0.10, "", 7, Kind::disconnected);
  send(0.20, R"({"x": 3, "y": 0})", 8);
  source_->service();
  EXPECT_EQ(dropped(PoseReject::other_sender), 0u);
  EXPECT_NEAR(source_->truth_at(at_s(0.2))->position_m.east_m, 3.0, 1e-9);
}

TEST_F(SocketSourceTest, ServiceHandlesABoundedNumberOfMessagesPerCall) {
  for (int i = 0; i < 1000; ++i) send(i * 0.001, "flood of garbage");
  source_->service();
  EXPECT_EQ(dropped(PoseReject::not_json), 256u);
  EXPECT_EQ(queue_.size(), 744u);
}

TEST_F(SocketSourceTest, CountsAreLoggedAtTheEnd) {
  send(0.0, R"({"x": 1, "y": 0})");
  send(0.1, "[]");
  source_->service();
  source_.reset();
  EXPECT_NE(sink_->text.find("pose input fake:1: 1 poses used, 1 dropped by reason: not_object 1"), std::string::npos)
      << sink_->text;
}

}  // namespace socket_source_test
}  // namespace
}  // namespace gpsemu::sources
