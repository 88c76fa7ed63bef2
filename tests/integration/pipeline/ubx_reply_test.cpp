// The u-blox answer path through a real pseudo-terminal: a client (opened as gpsd opens a
// receiver) writes a MON-VER poll and a CFG-RATE; servicing the output, as the epoch loop does
// when the pty is readable, writes MON-VER and the ACK back at once, long before the next epoch
// (PX4 waits 250 ms); the rate takes effect in the channel's following epochs.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/protocol/ublox/ublox_protocol.hpp"
#include "emulator/ubx/bytes.hpp"
#include "tests/support/read_deadline.hpp"
#include "transport/pty_output.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu {
namespace {
namespace ubx_reply_test {

using ubx::test::frames_in;

using namespace std::chrono_literals;

TEST(UbxReply, PollAndAckComeBackThroughThePtyBeforeAnyEpoch) {
  ChannelSettings settings;
  settings.origin = {43.0725, -89.4125, 260.0};
  const UtcNs t0 = parse_iso8601_utc("2024-05-01T12:00:00Z");
  Channel channel(settings, t0);
  ubx::SessionSettings ubx_settings;
  ubx_settings.start.model = ReceiverModel::ublox_m8n;
  ubx_settings.start.sentences = {};  // the channel's NMEA protocol writes the sentences in this test
  ubx_settings.start.measurement_period = 100ms;
  channel.add_protocol(std::make_unique<protocol::UbloxProtocol>(ubx_settings));

  Sink sink;
  std::vector<std::unique_ptr<transport::Output>> outputs;
  auto pty = std::make_unique<transport::PtyOutput>();
  transport::PtyOutput* out = pty.get();
  outputs.push_back(std::move(pty));
  const std::size_t i = sink.add(std::move(outputs));
  sink.attach_client_input(i, &channel);

  const int client = ::open(out->device_path().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  ASSERT_GE(client, 0);
  termios tio{};
  ASSERT_EQ(::tcgetattr(client, &tio), 0);
  ::cfmakeraw(&tio);
  ASSERT_EQ(::tcsetattr(client, TCSANOW, &tio), 0);

  const std::string request = ubx::frame_bytes(ubx::msg::mon_ver, "") +
                              ubx::frame_bytes(ubx::msg::cfg_rate, std::string("\xc8\x00\x01\x00\x00\x00", 6)) +
                              ubx::frame_bytes(ubx::msg::cfg_msg, std::string("\x01\x07\x01", 3));
  const auto sent = std::chrono::steady_clock::now();
  ASSERT_EQ(::write(client, request.data(), request.size()), static_cast<ssize_t>(request.size()));
  // The loop services a readable output at once; here: service until the answer is read.
  std::string answer;
  while (frames_in(answer).size() < 3 && std::chrono::steady_clock::now() - sent < 2s) {
    sink.service_all();
    answer += test::read_available(client, 5ms, 50ms);
  }
  const auto took = std::chrono::steady_clock::now() - sent;
  const auto frames = frames_in(answer);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].id, ubx::msg::mon_ver);
  EXPECT_EQ(frames[1].id, ubx::msg::ack_ack);
  EXPECT_EQ(frames[2].id, ubx::msg::ack_ack);
  EXPECT_LT(took, 250ms);
  EXPECT_EQ(out->stats().replies_written, 1u);
  EXPECT_EQ(out->stats().epochs_written, 0u);

  // 200 ms measurement period: of four 100 ms epochs, two carry NAV-PVT.
  int with_pvt = 0;
  for (int k = 0; k < 4; ++k) {
    (void)channel.step(t0 + std::chrono::milliseconds(100 * k), sources::Truth{});
    sink.prepare(i);
    sink.write(i, channel.bytes());
    const std::string epoch = test::read_available(client, 20ms, 1s);
    const auto epoch_frames = frames_in(epoch);
    with_pvt += epoch_frames.size() == 1 && epoch_frames[0].id == ubx::msg::nav_pvt ? 1 : 0;
    EXPECT_EQ(epoch.rfind("$GPRMC", 0), 0u);
  }
  EXPECT_EQ(with_pvt, 2);
  ::close(client);
}

}  // namespace ubx_reply_test
}  // namespace
}  // namespace gpsemu
