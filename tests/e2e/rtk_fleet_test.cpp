// --rtcm in a fleet (docs/rtk.md "Inputs"): each receiver listens on its own base-station port
// (`--rtcm udp:{P+i}`, or a [[receiver]] table's `rtcm` key). Corrections sent to receiver 1's
// port make receiver 1 RTK fixed; receiver 0, with no corrections on its port, stays autonomous.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include <GeographicLib/Geocentric.hpp>
#include <fmt/format.h>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"
#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/gpsd.hpp"
#include "tests/support/rtk_rover.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace rtk_fleet_test {

namespace fs = std::filesystem;
using namespace std::chrono;

std::string corrections(int k) {
  rtk::BasePosition b;
  b.station_id = 7;
  GeographicLib::Geocentric::WGS84().Forward(43.0725 + 0.001, -89.4125, 230.0, b.ecef_x_m, b.ecef_y_m, b.ecef_z_m);
  return rtk::rtcm3_frame_bytes(rtk::encode_base_position(b, false)) +
         rtk::rtcm3_frame_bytes(rtk::encode_msm(1077, 7, 345600000u + 100u * static_cast<unsigned>(k), 10, 2));
}

std::set<int> gga_qualities(const fs::path& file) {
  const std::vector<int> all = test::gga_qualities_in(file);
  return {all.begin(), all.end()};
}

TEST(RtkFleet, EachReceiverHasItsOwnCorrectionsPort) {
  const fs::path dir = test::scratch_root() / fmt::format("gpsemu_rtk_fleet_{}", ::getpid());
  fs::create_directories(dir);
  const int port = test::free_tcp_port();  // port and port + 1: free for UDP too, almost always
  test::Process gpsemu({GPSEMU_BINARY, "--receivers", "2", "--output", "file:" + (dir / "out{i}.nmea").string(),
                        "--rate", "5", "--duration", "3", "--rtcm", fmt::format("udp:{{{}+i}}", port),
                        "--rtk-convergence", "0.2,0.6,0", "--log-level", "info"});
  ASSERT_TRUE(gpsemu.wait_for_stderr(fmt::format("corrections on udp:127.0.0.1:{}", port + 1), seconds(20)))
      << gpsemu.stderr_text();
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port + 1));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  for (int k = 0; k < 20; ++k) {
    const std::string bytes = corrections(k);
    (void)::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
    std::this_thread::sleep_for(milliseconds(100));
  }
  ::close(fd);
  EXPECT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  EXPECT_EQ(gga_qualities(dir / "out0.nmea"), std::set<int>{1}) << gpsemu.stderr_text();
  const std::set<int> one = gga_qualities(dir / "out1.nmea");
  EXPECT_TRUE(one.contains(2) && one.contains(5) && one.contains(4)) << gpsemu.stderr_text();
  fs::remove_all(dir);
}

}  // namespace rtk_fleet_test
}  // namespace
}  // namespace gpsemu
