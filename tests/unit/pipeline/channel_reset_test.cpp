// A reset fault in a u-blox channel: silent for its boot, then a cold start (no fix until its
// TTFF, NAV-STATUS msss from the boot) with RAM reloaded from the layers, so the NAV-PVT a client
// turned on is off again; the client's configuration replayed after the reset takes effect, and
// the reset's own cold-start effect does not restart the receiver a second time.
#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "emulator/pipeline/channel.hpp"
#include "emulator/protocol/ublox/ublox_protocol.hpp"
#include "emulator/ubx/bytes.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu {
namespace {
namespace channel_reset_test {

using ubx::test::frames_in;
using std::chrono::seconds;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

const ubx::Frame* find(const std::vector<ubx::Frame>& frames, ubx::MessageId id) {
  for (const ubx::Frame& f : frames) {
    if (f.id == id) return &f;
  }
  return nullptr;
}

/// A u-blox M8N channel at Madison, the defaults otherwise.
ChannelSettings ublox_m8n_channel() {
  ChannelSettings settings;
  settings.origin = {43.0725, -89.4125, 260.0};
  ubx::SessionSettings ubx_settings;
  ubx_settings.start.model = ReceiverModel::ublox_m8n;
  settings.protocol = protocol::ublox_protocol(ubx_settings);
  return settings;
}

TEST(ChannelReset, SilentThenColdWithTheConfigurationLostUntilTheClientConfiguresAgain) {
  ChannelSettings settings = ublox_m8n_channel();
  settings.faults.faults.push_back(faults::make_fault(
      {{"kind", std::string("reset")}, {"at", 2.0}, {"silent_s", 2.0}, {"ttff_s", 3.0}}));
  Channel channel(settings, kT0);
  const std::string turn_on = ubx::frame_bytes(ubx::msg::cfg_msg, std::string("\x01\x07\x01", 3)) +
                              ubx::frame_bytes(ubx::msg::cfg_msg, std::string("\x01\x03\x01", 3));  // NAV-PVT, NAV-STATUS
  channel.client_wrote(turn_on, 1);
  (void)channel.take_reply(1);

  const auto epoch = [&](int s) {
    const UtcNs t = kT0 + seconds(s);
    for (const protocol::Effect& e : channel.protocol().take_effects()) {
      if (std::holds_alternative<protocol::ColdStart>(e.what)) channel.cold_start(t);  // as apply_protocol_effects does
    }
    const nmea::Fix fix = channel.step(t, sources::Truth{}).fix;
    return std::pair{fix, frames_in(channel.bytes())};
  };
  for (int s = 0; s < 2; ++s) {
    const auto [fix, frames] = epoch(s);
    ASSERT_TRUE(fix.has_fix()) << s;
    ASSERT_NE(find(frames, ubx::msg::nav_pvt), nullptr) << s;
  }
  for (int s = 2; s < 4; ++s) EXPECT_TRUE(epoch(s).second.empty() && channel.bytes().empty()) << "silent at " << s;
  EXPECT_EQ(channel.stats().epochs_silent, 2u);
  // Rebooted: NMEA only (the defaults), no fix, the UBX messages the client turned on are off.
  {
    const auto [fix, frames] = epoch(4);
    EXPECT_FALSE(fix.has_fix());
    EXPECT_TRUE(frames.empty());
    EXPECT_NE(channel.bytes().find("RMC,"), std::string::npos) << channel.bytes();
  }
  EXPECT_EQ(protocol::as_ublox(channel.protocol())->session().machine().stats().resets, 1u);
  // The client configures it again: it takes effect; the fix is back 5 s after the reset.
  channel.client_wrote(turn_on, 1);
  (void)channel.take_reply(1);
  for (int s = 5; s < 9; ++s) {
    const auto [fix, frames] = epoch(s);
    const ubx::Frame* pvt = find(frames, ubx::msg::nav_pvt);
    const ubx::Frame* status = find(frames, ubx::msg::nav_status);
    ASSERT_NE(pvt, nullptr) << s;
    ASSERT_NE(status, nullptr) << s;
    EXPECT_EQ(fix.has_fix(), s >= 7) << s;
    EXPECT_EQ(ubx::get_u1(pvt->payload, 20), s >= 7 ? 3 : 0) << s;
    EXPECT_EQ(ubx::get_u4(status->payload, 12), static_cast<std::uint32_t>(1000 * (s - 4))) << "msss from the boot";
    if (s == 7) {
      EXPECT_EQ(ubx::get_u4(status->payload, 8), 3000u) << "ttff";
    }
  }
}

// A client's CFG-RST (cold start, GNSS only): the channel restarts the model and the receiver's
// status, so the next NAV-STATUS has run 0 ms and no TTFF until the cold start's first fix, and
// the clock starts again from the seed (the same bias as at first).
TEST(ChannelReset, ACfgRstColdStartStartsTheRunTimeAndTheTimeAgain) {
  ChannelSettings settings = ublox_m8n_channel();
  settings.receiver.cold_start_s = 3.0;
  Channel channel(settings, kT0);
  channel.client_wrote(ubx::frame_bytes(ubx::msg::cfg_msg, std::string("\x01\x03\x01", 3)), 1);  // NAV-STATUS
  (void)channel.take_reply(1);
  const auto status_at = [&](int s) {
    const UtcNs t = kT0 + seconds(s);
    for (const protocol::Effect& e : channel.protocol().take_effects()) {
      if (std::holds_alternative<protocol::ColdStart>(e.what)) channel.cold_start(t);  // as apply_protocol_effects does
    }
    const ReceiverEpoch epoch = channel.step(t, sources::Truth{});
    const std::vector<ubx::Frame> frames = frames_in(channel.bytes());
    const ubx::Frame* status = find(frames, ubx::msg::nav_status);
    return std::pair{epoch, status ? status->payload : std::string()};
  };
  const auto [first, first_status] = status_at(0);
  ASSERT_FALSE(first_status.empty());
  EXPECT_EQ(ubx::get_u4(first_status, 12), 0u) << "msss: a cold start from the first epoch";
  for (int s = 1; s < 5; ++s) (void)status_at(s);
  const auto [before, before_status] = status_at(5);
  ASSERT_TRUE(before.fix.has_fix());
  EXPECT_EQ(ubx::get_u4(before_status, 12), 5000u) << "msss";
  EXPECT_EQ(ubx::get_u4(before_status, 8), 3000u) << "ttff";
  channel.client_wrote(ubx::frame_bytes(ubx::msg::cfg_rst, std::string("\xff\xff\x02\x00", 4)), 1);
  (void)channel.take_reply(1);
  const auto [after, after_status] = status_at(6);
  ASSERT_FALSE(after_status.empty());
  EXPECT_FALSE(after.fix.has_fix());
  EXPECT_EQ(ubx::get_u4(after_status, 12), 0u) << "msss";
  EXPECT_EQ(ubx::get_u4(after_status, 8), 0u) << "no TTFF before the new first fix";
  EXPECT_EQ(after.status.clock.bias_ns, first.status.clock.bias_ns) << "the clock from the seed again";
  for (int s = 7; s < 9; ++s) (void)status_at(s);
  const auto [fixed, fixed_status] = status_at(9);
  ASSERT_TRUE(fixed.fix.has_fix());
  EXPECT_EQ(ubx::get_u4(fixed_status, 8), 3000u) << "ttff of the cold start";
}

TEST(ChannelReset, AnNmeaReceiverRebootsToo) {
  ChannelSettings settings;
  settings.origin = {43.0725, -89.4125, 260.0};
  settings.faults.faults.push_back(faults::make_fault({{"kind", std::string("reset")}, {"at", 1.0}, {"silent_s", 1.0},
                                                       {"ttff_s", 2.0}}));
  Channel channel(settings, kT0);
  std::vector<bool> fixes;
  std::vector<bool> written;
  for (int s = 0; s < 6; ++s) {
    fixes.push_back(channel.step(kT0 + seconds(s), sources::Truth{}).fix.has_fix());
    written.push_back(!channel.bytes().empty());
  }
  EXPECT_EQ(written, (std::vector<bool>{true, false, true, true, true, true}));
  // (the silent epoch's fix is never written)
  EXPECT_TRUE(fixes[0]);
  EXPECT_FALSE(fixes[2]) << "cold after the boot";
  EXPECT_FALSE(fixes[3]);
  EXPECT_TRUE(fixes[4]) << "3 s after the reset";
  EXPECT_TRUE(fixes[5]);
}

}  // namespace channel_reset_test
}  // namespace
}  // namespace gpsemu
