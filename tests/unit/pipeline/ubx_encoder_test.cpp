// The u-blox encoder in a receiver channel: a client's poll written to an output is answered on
// that output at once, before any epoch (PX4 waits 250 ms for an ACK, an epoch may be a second
// away); after a CFG-MSG turning NAV-PVT on, the channel's next epoch carries it with the fix.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/pipeline/ubx_encoder.hpp"
#include "emulator/ubx/bytes.hpp"
#include "tests/support/ubx_frames.hpp"
#include "tests/support/talking_output.hpp"

namespace gpsemu {
namespace {

using test::TalkingOutput;
using ubx::test::frames_in;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

TEST(UbxEncoder, PollIsAnsweredOnTheOutputBeforeAnyEpoch) {
  ChannelSettings settings;
  settings.origin = {43.0725, -89.4125, 260.0};
  Channel channel(settings, kT0);
  ubx::SessionSettings ubx_settings;
  ubx_settings.start.model = ubx::ReceiverModel::ublox_m8n;
  ubx_settings.start.sentences = {};  // the channel's NMEA encoder writes the sentences here
  channel.add_encoder(std::make_unique<UbxEncoder>(ubx_settings));

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

TEST(UbxEncoder, BadFramesFromTheClientAreCountedAndNotAnswered) {
  ubx::SessionSettings settings;
  settings.start.model = ubx::ReceiverModel::ublox_f9p;
  UbxEncoder encoder(settings);
  std::string bad = ubx::frame_bytes(ubx::msg::mon_ver, "");
  bad.back() = static_cast<char>(bad.back() ^ 0x55);
  encoder.client_wrote(bad + "\xb5\x62\x06\x01\xff\xff", 1);
  EXPECT_TRUE(encoder.take_reply(1).empty());
  EXPECT_EQ(encoder.session().reader_stats().bad_checksum, 1u);
  EXPECT_EQ(encoder.session().reader_stats().too_long, 1u);
}

}  // namespace
}  // namespace gpsemu
