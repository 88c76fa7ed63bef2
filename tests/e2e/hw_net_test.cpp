// TCP and UDP outputs end to end through the binary: two TCP clients at once, one stalled (never
// reads), the other receiving whole valid epochs on time; UDP one datagram an epoch.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

#include "tests/support/nmea_check.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace hw_net_test {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

int connect_to(std::uint16_t port, int receive_buffer = 0) {
  const int fd = test::tcp_to(port, receive_buffer);
  EXPECT_GE(fd, 0) << "connect to 127.0.0.1:" << port;
  return fd;
}

TEST(NetEndToEndTest, TwoTcpClientsOneStalledTheOtherGetsWholeEpochsOnTime) {
  test::Process gpsemu({GPSEMU_BINARY, "--output", "tcp:127.0.0.1:0", "--rate", "10", "--duration", "4",
                        "--log-level", "info"});
  const auto line = gpsemu.wait_for_stderr("NMEA on tcp:127.0.0.1:", 10s);
  ASSERT_TRUE(line) << gpsemu.stderr_text();
  std::smatch m;
  ASSERT_TRUE(std::regex_search(*line, m, std::regex("tcp:127\\.0\\.0\\.1:([0-9]+)")));
  const auto port = static_cast<std::uint16_t>(std::stoi(m[1]));
  const int stalled = connect_to(port, 4096);  // connects, never reads
  const int reader = connect_to(port);

  std::string received;
  std::vector<Clock::time_point> arrivals;  // when each epoch's first sentence (RMC) arrived
  // Until the emulator finishes and closes the connection (or 10 s of silence).
  test::read_with_deadline(reader, {120s, 10s}, [&](std::string_view chunk) {
    const std::size_t before = received.size();
    received.append(chunk);
    for (std::size_t pos = received.find("RMC,", before >= 6 ? before - 6 : 0); pos != std::string::npos;
         pos = received.find("RMC,", pos + 1)) {
      arrivals.push_back(Clock::now());
    }
    return false;
  });
  EXPECT_EQ(gpsemu.wait(10s), 0) << gpsemu.stderr_text();
  ::close(stalled);
  ::close(reader);
  const test::SplitResult split = test::split_sentences(received);
  EXPECT_EQ(split.invalid, 0u);
  EXPECT_EQ(split.rest, "") << "half an epoch";
  ASSERT_GE(arrivals.size(), 30u) << gpsemu.stderr_text();
  Clock::duration worst_gap{};
  for (std::size_t i = 1; i < arrivals.size(); ++i) worst_gap = std::max(worst_gap, arrivals[i] - arrivals[i - 1]);
  EXPECT_LT(worst_gap, 400ms) << "the reading client was delayed";
  std::printf("tcp end to end: %zu epochs to the reading client beside a stalled one; worst gap between epochs "
              "%.1f ms (nominal 100)\n",
              arrivals.size(), std::chrono::duration<double, std::milli>(worst_gap).count());
}

TEST(NetEndToEndTest, UdpCarriesOneWholeEpochPerDatagram) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  const std::string spec = "udp:127.0.0.1:" + std::to_string(ntohs(addr.sin_port));
  test::Process gpsemu({GPSEMU_BINARY, "--output", spec, "--rate", "5", "--duration", "1.2", "--log-level", "warn"});
  std::vector<std::string> datagrams;  // one read, one datagram
  test::read_with_deadline(fd, {60s, 3s}, [&](std::string_view datagram) {
    datagrams.emplace_back(datagram);
    return datagrams.size() == 6;
  });
  EXPECT_EQ(gpsemu.wait(10s), 0) << gpsemu.stderr_text();
  ::close(fd);
  ASSERT_EQ(datagrams.size(), 6u);
  for (const auto& d : datagrams) {
    const test::SplitResult split = test::split_sentences(d);
    EXPECT_EQ(split.invalid, 0u);
    EXPECT_EQ(split.rest, "");
    EXPECT_EQ(std::count_if(split.sentences.begin(), split.sentences.end(),
                            [](const std::string& s) { return test::sentence_type(s) == "GGA"; }),
              1);
  }
}

}  // namespace hw_net_test
}  // namespace
}  // namespace gpsemu
