// The second-stage faults in a u-blox channel, as the UBX messages carry them: a sky-mask takes
// satellites out of NAV-SAT and NAV-PVT's numSV, a detected spoof sets NAV-STATUS spoofDetState 3
// (and moves NAV-PVT's position and velocity), a week-number rollover takes NAV-TIMEGPS's week
// back 1024 with iTOW unchanged; every message is back to normal after the faults.
#include <gtest/gtest.h>

#include <string>

#include "emulator/pipeline/channel.hpp"
#include "emulator/protocol/ublox/ublox_protocol.hpp"
#include "emulator/ubx/bytes.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu {
namespace {
namespace channel_ubx_faults_test {

using std::chrono::seconds;
using ubx::test::frames_in;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

struct Epoch {
  std::string pvt, status, sat, timegps;
};

TEST(ChannelUbxFaults, SkyMaskSpoofAndRolloverShowInTheNavMessages) {
  ChannelSettings settings;
  settings.origin = {43.0725, -89.4125, 260.0};
  ubx::SessionSettings ubx_settings;
  ubx_settings.start.model = ReceiverModel::ublox_m8n;
  ubx_settings.start.sentences = {};
  ubx_settings.start.ubx_messages = {ubx::msg::nav_pvt, ubx::msg::nav_status, ubx::msg::nav_sat, ubx::msg::nav_timegps};
  settings.protocol = protocol::ublox_protocol(ubx_settings);
  using faults::make_fault;
  settings.faults.faults = {
      make_fault({{"kind", std::string("sky-mask")}, {"at", 1.0}, {"duration", 1.0}, {"mask", std::string("0-180:90")}}),
      make_fault({{"kind", std::string("spoof")}, {"at", 2.0}, {"duration", 1.0}, {"speed_mps", 10.0},
                  {"detected", std::string("true")}}),
      make_fault({{"kind", std::string("time")}, {"at", 3.0}, {"duration", 1.0}, {"mode", std::string("rollover")}}),
  };
  Channel channel(settings, kT0);
  std::vector<Epoch> e;
  for (int s = 0; s < 5; ++s) {
    (void)channel.step(kT0 + seconds(s), sources::Truth{});
    Epoch got;
    for (const ubx::Frame& f : frames_in(channel.bytes())) {
      if (f.id == ubx::msg::nav_pvt) got.pvt = f.payload;
      if (f.id == ubx::msg::nav_status) got.status = f.payload;
      if (f.id == ubx::msg::nav_sat) got.sat = f.payload;
      if (f.id == ubx::msg::nav_timegps) got.timegps = f.payload;
    }
    ASSERT_FALSE(got.pvt.empty() || got.status.empty() || got.sat.empty() || got.timegps.empty()) << s;
    e.push_back(got);
  }
  const auto num_sv = [](const Epoch& x) { return ubx::get_u1(x.pvt, 23); };
  const auto sat_count = [](const Epoch& x) { return ubx::get_u1(x.sat, 5); };
  const auto spoof_state = [](const Epoch& x) { return (ubx::get_u1(x.status, 7) >> 3) & 3u; };
  const auto week = [](const Epoch& x) { return static_cast<int>(ubx::get_u2(x.timegps, 8)); };
  // sky-mask: half the sky gone from NAV-SAT and the solution.
  EXPECT_LT(sat_count(e[1]), sat_count(e[0]));
  EXPECT_LT(num_sv(e[1]), num_sv(e[0]));
  EXPECT_EQ(ubx::get_u1(e[1].pvt, 20), 3);
  // spoof: detected; position and north velocity moved.
  EXPECT_EQ(spoof_state(e[0]), 0u);
  EXPECT_EQ(spoof_state(e[2]), 3u);
  EXPECT_NEAR(static_cast<std::int32_t>(ubx::get_u4(e[2].pvt, 48)) / 1000.0, 10.0, 0.5) << "velN (m/s)";
  // rollover: the week 1024 back, the time of week unchanged.
  EXPECT_EQ(week(e[3]), week(e[0]) - 1024);
  EXPECT_EQ(ubx::get_u4(e[3].timegps, 0) - ubx::get_u4(e[0].timegps, 0), 3000u);
  // All back.
  EXPECT_EQ(sat_count(e[4]), sat_count(e[0]));
  EXPECT_EQ(spoof_state(e[4]), 0u);
  EXPECT_EQ(week(e[4]), week(e[0]));
}

}  // namespace channel_ubx_faults_test
}  // namespace
}  // namespace gpsemu
