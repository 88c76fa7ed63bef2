// The effects a u-blox client asks for, applied to a running receiver (pipeline/protocol_effects.hpp):
// CFG-PRT's baud on a real serial line (a socat pty pair: the ACK arrives at the old speed, then
// the line's termios speed changes), and CFG-RST's cold start (no fix again for --cold-start).
#include <gtest/gtest.h>

#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "emulator/model/time.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/pipeline/protocol_effects.hpp"
#include "emulator/protocol/ublox/ublox_protocol.hpp"
#include "emulator/ubx/bytes.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/socat_pair.hpp"
#include "transport/serial_output.hpp"

namespace gpsemu {
namespace {
namespace ubx_effects_test {

using namespace std::chrono_literals;

ChannelSettings ublox_channel() {
  ChannelSettings settings;
  settings.origin = {43.0725, -89.4125, 260.0};
  ubx::SessionSettings ubx;
  ubx.start.model = ReceiverModel::ublox_m8n;
  ubx.start.sentences = {};
  ubx.start.ubx_messages = {ubx::msg::nav_pvt};
  ubx.start.baud = 9600;
  settings.protocol = protocol::ublox_protocol(ubx);
  return settings;
}

std::string cfg_prt_uart1(std::uint32_t baud) {
  std::string p(20, '\0');
  p[0] = 1;                                   // UART1
  p[4] = '\xd0', p[5] = '\x08';               // mode 8N1
  for (int k = 0; k < 4; ++k) p[8 + k] = static_cast<char>((baud >> (8 * k)) & 0xff);
  p[12] = 0x07, p[14] = 0x03;                 // in UBX+NMEA+RTCM, out UBX+NMEA
  return ubx::frame_bytes(ubx::msg::cfg_prt, p);
}

TEST(UbxEffects, CfgPrtBaudIsAcknowledgedAtTheOldSpeedThenTheSerialLineChanges) {
  const auto dir = test::scratch_dir("ubx_effects", "baud");
  test::SocatPair pair(dir / "A", dir / "B");
  const UtcNs t0 = parse_iso8601_utc("2024-05-01T12:00:00Z");
  Channel channel(ublox_channel(), t0);
  Sink sink;
  std::vector<std::unique_ptr<transport::Output>> outputs;
  auto serial = std::make_unique<transport::SerialOutput>(transport::SerialTarget{pair.a(), std::nullopt},
                                                          transport::SerialOptions{.baud_bps = 9600});
  transport::SerialOutput* line = serial.get();
  outputs.push_back(std::move(serial));
  const std::size_t i = sink.add(std::move(outputs));
  sink.attach_client_input(i, &channel);
  const int client = test::open_raw(pair.b());
  ASSERT_GE(client, 0);

  const std::string request = cfg_prt_uart1(115200);
  ASSERT_EQ(::write(client, request.data(), request.size()), static_cast<ssize_t>(request.size()));
  const std::string ack = ubx::frame_bytes(ubx::msg::ack_ack, std::string("\x06\x00", 2));
  std::string answer;
  for (int k = 0; k < 100 && answer.find(ack) == std::string::npos; ++k) {
    sink.service_all();
    answer += test::read_available(client, 5ms, 50ms);
  }
  ASSERT_NE(answer.find(ack), std::string::npos) << "no ACK-ACK for CFG-PRT";
  termios tio{};
  ASSERT_EQ(::tcgetattr(line->poll_fd(), &tio), 0);
  EXPECT_EQ(::cfgetospeed(&tio), B9600) << "the ACK goes out at the old speed";

  const EpochGrid grid(5.0);
  ReceiverSchedule schedule(grid, grid.index_at_or_after(t0));
  ReceiverLine ubx_line = line_of(sink.outputs(i));
  EXPECT_EQ(ubx_line.baud, 9600u);
  apply_protocol_effects(channel, sink.outputs(i), schedule, ubx_line, t0, "");
  EXPECT_EQ(ubx_line.baud, 115200u);
  ASSERT_EQ(::tcgetattr(line->poll_fd(), &tio), 0);
  EXPECT_EQ(::cfgetospeed(&tio), B115200);
  EXPECT_EQ(::cfgetispeed(&tio), B115200);
  EXPECT_EQ(line->baud_bps(), 115200);
  EXPECT_NE(line->describe().find("@115200"), std::string::npos) << line->describe();
  // The epochs keep flowing on the line at its new speed.
  (void)channel.step(t0, sources::Truth{});
  sink.write(i, channel.bytes());
  EXPECT_NE(test::read_available(client, 50ms, 1s).find("\xb5\x62\x01\x07"), std::string::npos);
  ::close(client);
}

TEST(UbxEffects, CfgRstColdStartRestartsTheReceiverAtTheEpoch) {
  ChannelSettings settings = ublox_channel();
  settings.receiver.cold_start_s = 2.0;
  settings.receiver.cold_start_2d_s = 0.0;
  const UtcNs t0 = parse_iso8601_utc("2024-05-01T12:00:00Z");
  Channel channel(settings, t0);
  EXPECT_FALSE(channel.step(t0 + 1s, sources::Truth{}).fix.has_fix());
  EXPECT_TRUE(channel.step(t0 + 3s, sources::Truth{}).fix.has_fix());

  channel.client_wrote(ubx::frame_bytes(ubx::msg::cfg_rst, std::string("\xff\xff\x02\x00", 4)), 1);
  EXPECT_TRUE(channel.take_reply(1).empty()) << "a u-blox does not acknowledge CFG-RST";
  const EpochGrid grid(1.0);
  ReceiverSchedule schedule(grid, grid.index_at_or_after(t0));
  ReceiverLine line;
  apply_protocol_effects(channel, {}, schedule, line, t0 + 4s, "");
  EXPECT_FALSE(channel.step(t0 + 4s, sources::Truth{}).fix.has_fix());
  EXPECT_FALSE(channel.step(t0 + 5s, sources::Truth{}).fix.has_fix());
  EXPECT_TRUE(channel.step(t0 + 6s, sources::Truth{}).fix.has_fix());
}

}  // namespace ubx_effects_test
}  // namespace
}  // namespace gpsemu
