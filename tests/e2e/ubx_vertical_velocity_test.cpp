// Vertical velocity end to end (issue 35): a vehicle climbing on a known path (sim:waypoints, a
// leg 30 m north and 40 m up at 5 m/s: 3 m/s north, 4 m/s up) reports velD = -4 m/s in NAV-PVT
// (mm/s) and NAV-VELNED (cm/s, with the 3-D speed 5 m/s beside the ground speed 3 m/s), and an
// ECEF velocity of 5 m/s whose up component is 4 m/s in NAV-VELECEF, as ArduPilot's EKF3 and PX4's
// EKF2 read them. NAV-VELNED and NAV-VELECEF are on from the receiver's stored configuration
// (--receiver-state), NAV-PVT from --protocol ubx; --noise none: the velocity is the truth's.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu {
namespace {
namespace ubx_vertical_velocity_test {

using namespace std::chrono;

std::int32_t i4(std::string_view p, std::size_t at) { return static_cast<std::int32_t>(ubx::get_u4(p, at)); }

TEST(UbxVerticalVelocity, AClimbingVehicleReportsVelDInNavPvtVelnedAndVelecef) {
  const std::filesystem::path dir = test::scratch_dir("ubx_vertical_velocity", "climb");
  const auto route = test::write_file(dir / "climb.csv", "east_m,north_m,up_m,speed_mps\n0,0,0,5\n0,30,40,5\n");
  // CFG-MSGOUT-UBX_NAV_VELNED_UART1 and CFG-MSGOUT-UBX_NAV_VELECEF_UART1, saved in flash.
  const auto state = test::write_file(
      dir / "state.txt", "gpsemu u-blox receiver state 1\nmodel ublox-f9p\nflash key 20910043 1\nflash key 2091003e 1\n");
  const std::filesystem::path out = dir / "out.ubx";
  test::Process gpsemu({GPSEMU_BINARY, "--receiver", "ublox-f9p", "--protocol", "ubx", "--source",
                        "sim:waypoints:" + route.string(), "--noise", "none", "--rate", "5", "--fast", "--duration",
                        "4", "--start-time", "2026-01-01T00:00:00Z", "--receiver-state", state.string(), "--output",
                        "file:" + out.string(), "--log-level", "warn"});
  ASSERT_EQ(gpsemu.wait(seconds(30)), 0) << gpsemu.stderr_text();
  int pvt = 0, velned = 0, velecef = 0;
  const double lat = 43.0725 * std::numbers::pi / 180.0, lon = -89.4125 * std::numbers::pi / 180.0;  // the origin
  for (const ubx::Frame& f : ubx::test::frames_in(test::read_file(out))) {
    if (f.id == ubx::msg::nav_pvt && f.payload.size() == 92 && ubx::get_u1(f.payload, 20) == 3) {
      ++pvt;
      EXPECT_NEAR(i4(f.payload, 48), 3000, 2) << "velN mm/s";
      EXPECT_NEAR(i4(f.payload, 56), -4000, 2) << "velD mm/s";
      EXPECT_NEAR(i4(f.payload, 60), 3000, 2) << "gSpeed mm/s";
    } else if (f.id == ubx::MessageId{0x01, 0x12} && f.payload.size() == 36) {
      ++velned;
      EXPECT_NEAR(i4(f.payload, 12), -400, 1) << "velD cm/s";
      EXPECT_NEAR(ubx::get_u4(f.payload, 16), 500, 1) << "speed (3-D) cm/s";
      EXPECT_NEAR(ubx::get_u4(f.payload, 20), 300, 1) << "gSpeed cm/s";
    } else if (f.id == ubx::MessageId{0x01, 0x11} && f.payload.size() == 20) {
      ++velecef;
      const double x = i4(f.payload, 4), y = i4(f.payload, 8), z = i4(f.payload, 12);
      EXPECT_NEAR(std::sqrt(x * x + y * y + z * z), 500, 2) << "|ecefV| cm/s";
      const double up = std::cos(lat) * std::cos(lon) * x + std::cos(lat) * std::sin(lon) * y + std::sin(lat) * z;
      EXPECT_NEAR(up, 400, 2) << "ecefV up cm/s";
    }
  }
  EXPECT_GE(pvt, 15);
  EXPECT_EQ(velned, pvt);
  EXPECT_EQ(velecef, pvt);
  std::filesystem::remove_all(dir);
}

}  // namespace ubx_vertical_velocity_test
}  // namespace
}  // namespace gpsemu
