// The emulator's producer (pipeline/channel_set.hpp): each receiver on its own schedule, the loop's
// timeline their merge. A u-blox receiver whose client asks for 200 ms has epochs every 200 ms
// on the second's fifths from the epoch after, while an NMEA receiver beside it keeps --rate's
// grid (the same epochs and bytes as alone); --duration ends the run at the same time whatever
// the rates; the schedule alone (receiver_schedule.hpp) switches grids and back.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "emulator/pipeline/channel_set.hpp"
#include "emulator/protocol/ublox/ublox_protocol.hpp"
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "emulator/ubx/solution_grid.hpp"
#include "tests/support/talking_output.hpp"

namespace gpsemu {
namespace {
namespace channel_set_test {

using test::TalkingOutput;

using namespace std::chrono_literals;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

class StillSource final : public sources::PoseSource {
 public:
  std::optional<sources::Truth> truth_at(UtcNs) override { return sources::Truth{}; }
  [[nodiscard]] std::string describe() const override { return "still"; }
};

std::unique_ptr<Channel> channel(bool ublox) {
  ChannelSettings s;
  s.origin = {43.0725, -89.4125, 260.0};
  if (ublox) {
    ubx::SessionSettings u;
    u.start.model = ReceiverModel::ublox_m8n;
    u.start.sentences = {};
    u.start.ubx_messages = {ubx::msg::nav_pvt};
    s.protocol = protocol::ublox_protocol(u);
  }
  auto ch = std::make_unique<Channel>(s, kT0);
  ch->set_source(std::make_unique<StillSource>());
  return ch;
}

std::string cfg_rate(std::uint16_t meas_ms) {
  std::string p;
  ubx::put_u2(p, meas_ms);
  ubx::put_u2(p, 1);
  ubx::put_u2(p, 1);
  return ubx::frame_bytes(ubx::msg::cfg_rate, p);
}

struct Epoch {
  std::chrono::milliseconds at;  ///< since kT0
  std::vector<std::size_t> sending;
  friend bool operator==(const Epoch&, const Epoch&) = default;
};

/// Runs at most `max_epochs` epochs; receiver 0's bytes are appended to `first_bytes`.
std::vector<Epoch> run(ChannelSet& set, std::size_t max_epochs, std::string& first_bytes) {
  std::vector<Epoch> epochs;
  UtcNs t{};
  while (epochs.size() < max_epochs && set.next_epoch(t)) {
    Epoch e{std::chrono::duration_cast<std::chrono::milliseconds>(t - kT0), {}};
    for (std::size_t i = 0; i < set.size(); ++i) {
      if (!set.active(i)) continue;
      const std::string_view bytes = set.produce(i, t);
      if (i == 0) first_bytes += bytes;
      e.sending.push_back(i);
    }
    epochs.push_back(e);
  }
  return epochs;
}

TEST(ChannelSet, AUbloxAskingTwoHundredMillisecondsGetsItsOwnEpochsBesideAnNmeaReceiver) {
  const Timeline timeline{EpochGrid(1.0), EpochGrid(1.0).index_at_or_after(kT0), 0ns};
  ChannelSet set(timeline, 3);  // --duration 3 at 1 Hz
  set.add(channel(false));
  set.add(channel(true));
  Sink sink;
  (void)sink.add({});
  TalkingOutput* client = test::add_talking_output(sink).client;
  sink.attach_client_input(1, &set.channel(1));
  set.attach(sink);
  std::vector<std::chrono::nanoseconds> finest;
  set.on_finest_period([&](std::chrono::nanoseconds p) { finest.push_back(p); });

  std::string nmea_bytes;
  EXPECT_EQ(run(set, 1, nmea_bytes), (std::vector<Epoch>{{0ms, {0, 1}}}));
  client->input = cfg_rate(200);
  sink.service_all();
  EXPECT_NE(client->written.find(ubx::frame_bytes(ubx::msg::ack_ack, std::string("\x06\x08", 2))),
            std::string::npos);
  // Applied at the receiver's next epoch (1 s), its epochs every 200 ms from then; the run ends
  // at 3 s as --duration says.
  const std::vector<Epoch> expected = {{1000ms, {0, 1}}, {1200ms, {1}}, {1400ms, {1}}, {1600ms, {1}},
                                       {1800ms, {1}},    {2000ms, {0, 1}}, {2200ms, {1}}, {2400ms, {1}},
                                       {2600ms, {1}},    {2800ms, {1}}};
  EXPECT_EQ(run(set, 100, nmea_bytes), expected);
  EXPECT_EQ(set.channel(0).stats().epochs_emitted, 3u);
  EXPECT_EQ(set.channel(1).stats().epochs_emitted, 11u);
  EXPECT_EQ(finest, (std::vector<std::chrono::nanoseconds>{200ms})) << "the clock's lateness follows";

  // The NMEA receiver wrote what it writes alone.
  const std::unique_ptr<Channel> alone = channel(false);
  std::string alone_bytes;
  for (int k = 0; k < 3; ++k) {
    (void)alone->step(kT0 + std::chrono::seconds(k));
    alone_bytes += alone->bytes();
  }
  EXPECT_EQ(nmea_bytes, alone_bytes);
}

// Issue 22, point 10: a client asks for one solution per 2.3 hours; the run still lasts its
// --duration: no receiver has an epoch left, so the run grid's last time (4 s of a 5 s run at
// 1 Hz) is an idle epoch, none due, for the loop to wait for with the port open.
TEST(ChannelSet, ARunWhoseReceiversHaveNoEpochLeftWaitsIdleForItsLastTime) {
  const Timeline timeline{EpochGrid(1.0), EpochGrid(1.0).index_at_or_after(kT0), 0ns};
  ChannelSet set(timeline, 5);  // --duration 5 at 1 Hz
  set.add(channel(true));
  Sink sink;
  TalkingOutput* client = test::add_talking_output(sink).client;
  sink.attach_client_input(0, &set.channel(0));
  set.attach(sink);
  std::string bytes;
  EXPECT_EQ(run(set, 1, bytes), (std::vector<Epoch>{{0ms, {0}}}));
  EXPECT_TRUE(set.any_due());
  std::string slow;
  ubx::put_u2(slow, 65535);
  ubx::put_u2(slow, 127);
  ubx::put_u2(slow, 1);
  client->input = ubx::frame_bytes(ubx::msg::cfg_rate, slow);
  sink.service_all();
  // Applied at 1 s; the next solution is hours away: 4 s is idle, then the run ends.
  UtcNs t{};
  ASSERT_TRUE(set.next_epoch(t));
  EXPECT_EQ(t, kT0 + 1s);
  EXPECT_TRUE(set.any_due());
  (void)set.produce(0, t);
  ASSERT_TRUE(set.next_epoch(t));
  EXPECT_EQ(t, kT0 + 4s);
  EXPECT_FALSE(set.any_due());
  EXPECT_FALSE(set.active(0));
  EXPECT_FALSE(set.next_epoch(t));
}

TEST(ReceiverSchedule, FollowsASolutionGridFromTheEpochAfterAndReturnsToTheRunGrid) {
  const EpochGrid grid(1.0);
  ReceiverSchedule schedule(grid, grid.index_at_or_after(kT0));
  EXPECT_EQ(schedule.next(), kT0);
  schedule.advance();
  EXPECT_EQ(schedule.next(), kT0 + 1s);
  EXPECT_EQ(schedule.period(), 1s);
  const ubx::SolutionGrid solutions{100ms, 1};
  schedule.follow(protocol::SolutionGrid{100ms, [solutions](UtcNs t) { return solutions.next_after(t); }}, kT0 + 1s);
  EXPECT_EQ(schedule.next(), kT0 + 1100ms);
  EXPECT_EQ(schedule.period(), 100ms);
  schedule.advance();
  EXPECT_EQ(schedule.next(), kT0 + 1200ms);
  schedule.follow(std::nullopt, kT0 + 1200ms);
  EXPECT_EQ(schedule.next(), kT0 + 2s);
  schedule.advance();
  EXPECT_EQ(schedule.next(), kT0 + 3s);
}

}  // namespace channel_set_test
}  // namespace
}  // namespace gpsemu
