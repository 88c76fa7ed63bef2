// The u-blox port behind the receiver protocol interface (protocol/ublox/ublox_protocol.hpp): in a
// receiver channel a client's poll written to an output is answered on that output at once, before
// any epoch (PX4 waits 250 ms for an ACK, an epoch may be a second away); after a CFG-MSG turning
// NAV-PVT on, the channel's next epoch carries it with the fix. The session's effects come out as
// the interface's: CFG-RATE a solution grid (the run's grid again for the start period; the
// model's fastest rate, with a warning, when a faster one is asked), CFG-PRT a baud, CFG-RST a
// cold start, each naming its message; a reset the emulator asks for reloads RAM and asks for no
// second cold start.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/protocol/ublox/ublox_protocol.hpp"
#include "emulator/ubx/bytes.hpp"
#include "tests/support/ubx_frames.hpp"
#include "tests/support/talking_output.hpp"

namespace gpsemu {
namespace {
namespace ublox_protocol_test {

using test::TalkingOutput;
using ubx::test::frames_in;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

TEST(UbloxProtocol, PollIsAnsweredOnTheOutputBeforeAnyEpoch) {
  ChannelSettings settings;
  settings.origin = {43.0725, -89.4125, 260.0};
  Channel channel(settings, kT0);
  ubx::SessionSettings ubx_settings;
  ubx_settings.start.model = ReceiverModel::ublox_m8n;
  ubx_settings.start.sentences = {};  // the channel's NMEA protocol writes the sentences here
  channel.add_protocol(std::make_unique<protocol::UbloxProtocol>(ubx_settings));

  Sink sink;
  const auto [client, i] = test::add_talking_output(sink);
  sink.attach_client_input(i, &channel);

  client->input = ubx::frame_bytes(ubx::msg::mon_ver, "") + ubx::frame_bytes(ubx::msg::cfg_msg, std::string("\x01\x07\x01", 3));
  sink.service_all();
  ASSERT_EQ(client->sent.size(), 1u);  // one reply write, no epoch yet
  const auto reply = frames_in(client->sent[0]);
  ASSERT_EQ(reply.size(), 2u);
  EXPECT_EQ(reply[0].id, ubx::msg::mon_ver);
  EXPECT_EQ(reply[1].id, ubx::msg::ack_ack);
  EXPECT_EQ(client->stats().replies_written, 1u);
  EXPECT_EQ(client->stats().epochs_written, 0u);
  // The reply's bytes are counted apart from the epochs' (issue 22, point 11), and an epoch with
  // nothing to send is not written: counted as empty.
  EXPECT_EQ(client->stats().reply_bytes_written, client->sent[0].size());
  EXPECT_EQ(client->stats().bytes_written, 0u);
  EXPECT_EQ(client->write_epoch(""), transport::WriteStatus::ok);
  EXPECT_EQ(client->sent.size(), 1u);
  EXPECT_EQ(client->stats().epochs_empty, 1u);
  EXPECT_EQ(client->stats().epochs_written, 0u);

  (void)channel.step(kT0, sources::Truth{});
  const auto epoch = frames_in(channel.bytes());
  ASSERT_EQ(epoch.size(), 1u);
  EXPECT_EQ(epoch[0].id, ubx::msg::nav_pvt);
  EXPECT_EQ(ubx::get_u1(epoch[0].payload, 20), 3);  // 3-D fix
  EXPECT_EQ(channel.bytes().rfind("$GPRMC", 0), 0u);  // NMEA first, then UBX
}

TEST(UbloxProtocol, BadFramesFromTheClientAreCountedAndNotAnswered) {
  ubx::SessionSettings settings;
  settings.start.model = ReceiverModel::ublox_f9p;
  protocol::UbloxProtocol encoder(settings);
  std::string bad = ubx::frame_bytes(ubx::msg::mon_ver, "");
  bad.back() = static_cast<char>(bad.back() ^ 0x55);
  encoder.client_wrote(bad + "\xb5\x62\x06\x01\xff\xff", 1);
  EXPECT_TRUE(encoder.take_reply(1).empty());
  EXPECT_EQ(encoder.session().reader_stats().bad_checksum, 1u);
  EXPECT_EQ(encoder.session().reader_stats().too_long, 1u);
}

std::string cfg_rate(std::uint16_t meas_ms) {
  std::string p;
  ubx::put_u2(p, meas_ms);
  ubx::put_u2(p, 1);  // navRate
  ubx::put_u2(p, 1);  // timeRef GPS
  return ubx::frame_bytes(ubx::msg::cfg_rate, p);
}

ubx::SessionSettings m8n_at(std::chrono::milliseconds period) {
  ubx::SessionSettings s;
  s.start.model = ReceiverModel::ublox_m8n;
  s.start.measurement_period = period;
  return s;
}

TEST(UbloxProtocol, CfgRateIsASolutionGridOrTheRunGridAgainAtTheStartPeriod) {
  using namespace std::chrono_literals;
  protocol::UbloxProtocol port(m8n_at(1000ms));
  port.client_wrote(cfg_rate(200), 1);
  EXPECT_TRUE(port.period_change_pending());
  auto effects = port.take_effects();
  ASSERT_EQ(effects.size(), 1u);
  EXPECT_EQ(effects[0].origin, "u-blox CFG-RATE");
  const auto& changed = std::get<protocol::PeriodChanged>(effects[0].what);
  ASSERT_TRUE(changed.grid.has_value());
  EXPECT_EQ(changed.grid->period, 200ms);
  EXPECT_EQ(changed.grid->next_after(kT0 + 10ms), kT0 + 200ms);
  EXPECT_TRUE(changed.warning.empty());
  EXPECT_FALSE(port.period_change_pending());
  // Faster than an M8N navigates: acknowledged, solutions at its fastest, and a warning says so.
  port.client_wrote(cfg_rate(25), 1);
  effects = port.take_effects();
  const auto& fastest = std::get<protocol::PeriodChanged>(effects.at(0).what);
  ASSERT_TRUE(fastest.grid.has_value());
  EXPECT_EQ(fastest.grid->period, 100ms);
  EXPECT_NE(fastest.warning.find("a solution every 25 ms asked"), std::string::npos) << fastest.warning;
  // The start period again: the run's grid.
  port.client_wrote(cfg_rate(1000), 1);
  effects = port.take_effects();
  EXPECT_FALSE(std::get<protocol::PeriodChanged>(effects.at(0).what).grid.has_value());
}

TEST(UbloxProtocol, BaudAndColdStartNameTheirMessage) {
  ubx::SessionSettings f9p = m8n_at(std::chrono::milliseconds{1000});
  f9p.start.model = ReceiverModel::ublox_f9p;
  protocol::UbloxProtocol port(f9p);
  port.client_wrote(ubx::frame_bytes(ubx::msg::cfg_valset, ubx::test::valset({{ubx::key::uart1_baudrate, 115200}})) +
                        ubx::frame_bytes(ubx::msg::cfg_rst, std::string("\xff\xff\x02\x00", 4)),
                    1);
  const auto effects = port.take_effects();
  ASSERT_EQ(effects.size(), 2u);
  EXPECT_EQ(effects[0].origin, "u-blox CFG-PRT");
  EXPECT_EQ(std::get<protocol::BaudChanged>(effects[0].what).baud_bps, 115200u);
  EXPECT_EQ(effects[1].origin, "u-blox CFG-RST");
  EXPECT_TRUE(std::holds_alternative<protocol::ColdStart>(effects[1].what));
}

TEST(UbloxProtocol, AResetAskedForReloadsRamAndAsksForNoSecondColdStart) {
  using namespace std::chrono_literals;
  protocol::UbloxProtocol port(m8n_at(1000ms));
  port.client_wrote(cfg_rate(200), 1);
  (void)port.take_reply(1);
  (void)port.take_effects();
  port.reset(protocol::ResetKind::hardware_cold);
  EXPECT_TRUE(port.take_reply(1).empty());
  EXPECT_EQ(port.session().machine().stats().resets, 1u);
  EXPECT_EQ(port.session().reader_stats().frames_ok, 1u) << "no frame is forged";
  const auto effects = port.take_effects();
  ASSERT_EQ(effects.size(), 1u) << "the period back to the start's; no cold start";
  EXPECT_FALSE(std::get<protocol::PeriodChanged>(effects[0].what).grid.has_value());
  EXPECT_NE(port.configuration_summary().find("1 resets reloaded RAM"), std::string::npos);
}

}  // namespace ublox_protocol_test
}  // namespace
}  // namespace gpsemu
