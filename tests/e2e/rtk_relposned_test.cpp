// An F9P rover with a fixed base station (docs/rtk.md "NAV-RELPOSNED"): the client turns on
// NAV-RELPOSNED and NAV-PVT on the u-blox port and writes a base's RTCM3 (1006 300 m north of the
// origin + GPS MSM7, the project's encoder) into the same port, as PX4/ArduPilot inject it. The
// relative position is the rover's reported position minus the base's (checked against NAV-PVT's
// position of the same epoch and the 1006), its flags follow the RTK state (carrSoln none, float,
// fixed; isMoving and relPosHeadingValid 0). With RTCM3 input turned off on the port
// (CFG-UART1INPROT-RTCM3X = 0) the same bytes are ignored: no differential solution, and the
// summary says why.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <GeographicLib/Geocentric.hpp>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/static_base_relpos.hpp"
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "emulator/ubx/relposned.hpp"
#include "tests/support/rtk_rover.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu {
namespace {
namespace rtk_relposned_test {

/// What the client read from the port while it wrote `prefix` then 20 epochs of corrections.
struct RoverRun {
  std::vector<ubx::Frame> frames;
  std::string log;
};

RoverRun run_rover(const std::string& prefix) {
  test::RoverClient client;
  client.setup = ubx::frame_bytes(ubx::msg::cfg_msg, std::string("\x01\x3C\x01", 3)) +          // NAV-RELPOSNED
                 ubx::frame_bytes(ubx::msg::cfg_msg, std::string("\x01\x07\x01", 3)) + prefix;  // NAV-PVT
  client.settle = std::chrono::milliseconds(300);
  client.epochs = 20;
  const test::RoverRun run = test::run_f9p_rover(std::to_string(prefix.size()), "3.5", client);
  return {ubx::test::frames_in(run.bytes), run.log};
}

constexpr std::uint32_t kFixOk = 1u << 0, kDiff = 1u << 1, kValid = 1u << 2, kMoving = 1u << 5, kHeadingValid = 1u << 8;

TEST(RtkRelPosNed, StaticBaseRoverReportsTheBaselineAndFollowsTheRtkState) {
  const RoverRun run = run_rover("");
  // NAV-PVT's position by iTOW, to check each NAV-RELPOSNED against.
  std::map<std::uint32_t, std::array<double, 3>> pvt_ecef;
  for (const ubx::Frame& f : run.frames) {
    if (f.id != ubx::msg::nav_pvt || f.payload.size() != 92) continue;
    const double lon = ubx::get_i4(f.payload, 24) * 1e-7, lat = ubx::get_i4(f.payload, 28) * 1e-7;
    const double h = ubx::get_i4(f.payload, 32) * 1e-3;
    std::array<double, 3> e{};
    GeographicLib::Geocentric::WGS84().Forward(lat, lon, h, e[0], e[1], e[2]);
    pvt_ecef[ubx::get_u4(f.payload, 0)] = e;
  }
  std::vector<unsigned> carrier;  // carrSoln of each valid epoch
  int checked = 0;
  for (const ubx::Frame& f : run.frames) {
    if (f.id != ubx::msg::nav_relposned) continue;
    const ubx::RelPosNedFields r = ubx::read_relposned(f.payload);
    ASSERT_EQ(r.version, 1) << "payload of " << f.payload.size() << " bytes";
    EXPECT_EQ(r.flags & (kMoving | kHeadingValid), 0u);
    EXPECT_NE(r.flags & kFixOk, 0u);
    if ((r.flags & kValid) == 0) continue;
    EXPECT_NE(r.flags & kDiff, 0u);
    carrier.push_back((r.flags >> 3) & 3u);
    const auto pvt = pvt_ecef.find(r.itow_ms);
    if (pvt == pvt_ecef.end()) continue;
    // rover - base in the base's NED: about 300 m south, to the centimetre of what NAV-PVT says.
    const rtk::NedOffset want = rtk::ned_from(test::base_300m_north(), pvt->second[0], pvt->second[1], pvt->second[2]);
    EXPECT_NEAR(r.n_cm + r.hp_n * 0.01, want.north_m * 100.0, 3.0);
    EXPECT_NEAR(r.e_cm + r.hp_e * 0.01, want.east_m * 100.0, 3.0);
    EXPECT_NEAR(r.d_cm + r.hp_d * 0.01, want.down_m * 100.0, 3.0);
    EXPECT_NEAR(r.n_cm, -30020, 200);
    EXPECT_NEAR(r.length_cm * 0.01, std::hypot(want.north_m, want.east_m, want.down_m), 0.03);
    EXPECT_GT(r.acc_n, 0u);
    ++checked;
  }
  EXPECT_GE(checked, 8) << run.log;
  // none (DGPS) -> float -> fixed, in that order.
  ASSERT_FALSE(carrier.empty()) << run.log;
  EXPECT_TRUE(std::is_sorted(carrier.begin(), carrier.end())) << run.log;
  EXPECT_EQ(carrier.front(), 0u);
  EXPECT_NE(std::find(carrier.begin(), carrier.end(), 1u), carrier.end());
  EXPECT_EQ(carrier.back(), 2u);
}

TEST(RtkRelPosNed, RtcmInputOffOnThePortIgnoresTheCorrections) {
  constexpr std::uint32_t kUart1InprotRtcm3x = 0x10730004;
  const RoverRun run = run_rover(ubx::frame_bytes(ubx::msg::cfg_valset, ubx::test::valset({{kUart1InprotRtcm3x, 0}})));
  int relpos = 0;
  for (const ubx::Frame& f : run.frames) {
    if (f.id == ubx::msg::nav_relposned) {
      ++relpos;
      EXPECT_EQ(ubx::read_relposned(f.payload).flags, kFixOk);
    }
    if (f.id == ubx::msg::nav_pvt && f.payload.size() == 92) {
      EXPECT_EQ(ubx::get_u1(f.payload, 21) & 0xC2u, 0u);  // neither diffSoln nor carrSoln
    }
  }
  EXPECT_GE(relpos, 10) << run.log;
  EXPECT_NE(run.log.find("RTCM3 frames (0 bad CRC, 40 ignored: the port's input protocols exclude RTCM3)"),
            std::string::npos)
      << run.log;
  EXPECT_EQ(run.log.find("RTK: "), std::string::npos) << run.log;
}

}  // namespace rtk_relposned_test
}  // namespace
}  // namespace gpsemu
