// The RTCM3 input (--rtcm) beside hostile or broken peers, through the binary in real time at 5 Hz:
// on UDP a second sender's junk datagrams before each of the base's (one byte stream once: 60 of 72
// frames lost, RTK stuck at DGPS) are kept apart, then dropped and counted once the base is known;
// on TCP four idle connections do not keep the real base out (a connection that never gave a good
// frame gives its slot up), and a connection flooding junk beside the base does not starve it
// (the fix stays RTK fixed while the base sends). Each refusal and drop is in the exit summary.
// Real time is the subject (correction ages and the flood beside the base are wall time), so each
// run lasts only while the base sends (about 3 s) and is ended by SIGTERM.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <signal.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

#include <fmt/format.h>

#include "tests/support/gpsd.hpp"
#include "tests/support/process.hpp"
#include "tests/support/rtk_rover.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace rtk_input_hostile_test {

namespace fs = std::filesystem;
using namespace std::chrono;

void send_datagram(int fd, int port, const std::string& bytes) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  (void)::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
}

/// Epochs of RTK fixed (4) in a row at most.
std::size_t longest_fixed(const std::vector<int>& q) {
  std::size_t best = 0, run = 0;
  for (const int x : q) {
    run = x == 4 ? run + 1 : 0;
    best = std::max(best, run);
  }
  return best;
}

std::vector<std::string> gpsemu_args(const fs::path& file, const std::string& rtcm) {
  return {GPSEMU_BINARY, "--output", "file:" + file.string(), "--rate", "5", "--duration", "30", "--rtcm", rtcm,
          "--rtk-convergence", "0.2,0.6,0", "--rtk-timeouts", "0.5,1.1,1.7"};
}

TEST(RtkInputHostile, UdpFramesAreAssembledPerSenderAndOnlyTheBasesAreUsed) {
  const auto dir = test::scratch_dir("rtk", "udp-senders");
  const int port = test::free_tcp_port();
  test::Process gpsemu(gpsemu_args(dir / "out.nmea", fmt::format("udp:{}", port)));
  ASSERT_TRUE(gpsemu.wait_for_stderr("reading RTCM3 corrections", seconds(20))) << gpsemu.stderr_text();
  const int base = ::socket(AF_INET, SOCK_DGRAM, 0), other = ::socket(AF_INET, SOCK_DGRAM, 0);
  const std::string junk("\xD3\x03\xFF", 3);  // a frame header that swallowed the base's bytes
  for (int k = 0; k < 30; ++k) {
    send_datagram(other, port, junk);
    if (k == 0) send_datagram(base, port, test::base_1006());
    send_datagram(base, port, test::base_epoch(k));
    test::pump_for(gpsemu, milliseconds(100));
  }
  ::close(base);
  ::close(other);
  gpsemu.signal(SIGTERM);  // real time only as long as the base sends (the ages are wall time)
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  const std::string err = gpsemu.stderr_text();
  EXPECT_NE(err.find("1077 x30"), std::string::npos) << err;  // every one of the base's epochs
  EXPECT_NE(err.find("1006 x31"), std::string::npos) << err;
  EXPECT_NE(err.find(" 0 bad CRC dropped"), std::string::npos) << err;
  EXPECT_NE(err.find("29 datagram(s) of other senders dropped"), std::string::npos) << err;
  EXPECT_GE(longest_fixed(test::gga_qualities_in(dir / "out.nmea")), 10u) << err;
  fs::remove_all(dir);
}

TEST(RtkInputHostile, IdleAndJunkTcpConnectionsNeitherKeepOutNorStarveTheBase) {
  const auto dir = test::scratch_dir("rtk", "tcp-peers");
  const int port = test::free_tcp_port();
  test::Process gpsemu(gpsemu_args(dir / "out.nmea", fmt::format("tcp:127.0.0.1:{}", port)));
  ASSERT_TRUE(gpsemu.wait_for_stderr("reading RTCM3 corrections", seconds(20))) << gpsemu.stderr_text();
  // Four idle connections take every slot.
  std::vector<int> idle;
  for (int k = 0; k < 4; ++k) idle.push_back(test::connect_to_loopback(::socket(AF_INET, SOCK_STREAM, 0), port));
  test::pump_for(gpsemu, milliseconds(300));
  // The base comes, and a connection that floods junk beside it.
  const int base = test::connect_to_loopback(::socket(AF_INET, SOCK_STREAM, 0), port);
  ASSERT_GE(base, 0);
  std::atomic<bool> stop{false};
  std::thread flood([&] {
    const int fd = test::connect_to_loopback(::socket(AF_INET, SOCK_STREAM, 0), port);
    const std::string junk(4096, '\xD3');
    while (!stop && fd >= 0 && ::send(fd, junk.data(), junk.size(), MSG_NOSIGNAL) > 0) {
    }
    if (fd >= 0) ::close(fd);
  });
  bool base_open = true;
  for (int k = 0; k < 20 && base_open; ++k) {
    std::string bytes = k == 0 ? test::base_1006() : "";
    bytes += test::base_epoch(k);
    base_open = ::send(base, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
    test::pump_for(gpsemu, milliseconds(100));
  }
  EXPECT_TRUE(base_open) << "the base was closed";
  stop = true;
  flood.join();
  ::close(base);
  for (const int fd : idle) ::close(fd);
  gpsemu.signal(SIGTERM);
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  const std::string err = gpsemu.stderr_text();
  EXPECT_NE(err.find("1077 x20"), std::string::npos) << err;
  EXPECT_NE(err.find("closed to make room"), std::string::npos) << err;
  EXPECT_EQ(err.find(" 0 closed to make room"), std::string::npos) << err;
  // Fixed from convergence to the end of the base's 2 s (about 7 epochs at 5 Hz), never float between.
  EXPECT_GE(longest_fixed(test::gga_qualities_in(dir / "out.nmea")), 6u) << err;
  fs::remove_all(dir);
}

}  // namespace rtk_input_hostile_test
}  // namespace
}  // namespace gpsemu
