// The receiver channel (emulator/pipeline/channel.hpp): one fix an epoch published by each encoder
// in turn (a second protocol plugs in beside NMEA), what a client writes to an output reaching
// every encoder through the sink, and the channel's bytes being what format_epoch() writes.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/epoch_text.hpp"
#include "emulator/pipeline/sink.hpp"
#include "tests/support/talking_output.hpp"

namespace gpsemu {
namespace {
namespace channel_test {

using test::TalkingOutput;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

/// A second protocol: one line an epoch, and it records what clients wrote.
class TagProtocol final : public protocol::ReceiverProtocol {
 public:
  [[nodiscard]] std::size_t widest_epoch_bytes(const Geometry& /*sky*/) const override { return 9; }
  [[nodiscard]] std::string name() const override { return "TAG"; }
  [[nodiscard]] std::string written() const override { return "TAG"; }
  void encode(const ReceiverEpoch& epoch, std::string& out) override {
    out += epoch.fix.has_fix() ? "TAG fix\r\n" : "TAG none\r\n";
  }
  void client_wrote(std::string_view bytes, transport::ClientId /*client*/) override { heard += bytes; }
  std::string heard;
};

ChannelSettings settings() {
  ChannelSettings s;
  s.origin = {43.0725, -89.4125, 260.0};
  return s;
}

TEST(Channel, EachProtocolPublishesTheSameFixInTheOrderAdded) {
  Channel channel(settings(), kT0);
  auto tag = std::make_unique<TagProtocol>();
  channel.add_protocol(std::move(tag));
  const nmea::Fix fix = channel.step(kT0, sources::Truth{}).fix;
  ASSERT_TRUE(fix.has_fix());
  std::string nmea_only;
  format_epoch(fix, channel.settings().format, nmea_only);
  EXPECT_EQ(channel.bytes(), nmea_only + "TAG fix\r\n");
  (void)channel.step(kT0 + std::chrono::seconds(1), std::nullopt);
  EXPECT_EQ(channel.stats().epochs_without_fix, 1u);
  EXPECT_NE(channel.bytes().find("TAG none\r\n"), std::string::npos);
}

TEST(Channel, WhatAClientWritesReachesEveryProtocolThroughTheSink) {
  Channel channel(settings(), kT0);
  auto tag = std::make_unique<TagProtocol>();
  TagProtocol* heard = tag.get();
  channel.add_protocol(std::move(tag));
  Sink sink;
  const auto [client, i] = test::add_talking_output(sink);
  sink.service_all();  // no channel attached yet: dropped
  client->input = "dropped";
  sink.service_all();
  EXPECT_TRUE(heard->heard.empty());
  sink.attach_client_input(i, &channel);
  client->input = "\xb5\x62\x06\x01";
  sink.service_all();
  EXPECT_EQ(heard->heard, "\xb5\x62\x06\x01");
}

}  // namespace channel_test
}  // namespace
}  // namespace gpsemu
