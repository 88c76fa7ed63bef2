// UDP output with real sockets on loopback: one datagram an epoch, nobody listening is not an
// error, specs and start-up errors.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <string>

#include "tests/support/read_deadline.hpp"
#include "transport/output_spec.hpp"
#include "transport/udp_output.hpp"

namespace gpsemu::transport {
namespace {
namespace udp_test {

using namespace std::chrono_literals;

/// A bound UDP socket on 127.0.0.1 (any port); returns {fd, port}.
std::pair<int, std::uint16_t> bind_receiver() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  return {fd, ntohs(addr.sin_port)};
}

std::string receive_datagram(int fd) {
  bool received = false;
  const test::ReadResult r = test::read_with_deadline(fd, {2s}, [&](std::string_view) {
    return received = true;  // one read, one datagram
  });
  return received ? r.bytes : r.error != 0 ? "(error)" : "(nothing)";
}

TEST(UdpOutputTest, OneDatagramAnEpoch) {
  const auto [fd, port] = bind_receiver();
  UdpOutput out("127.0.0.1", port);
  EXPECT_EQ(out.describe(), "udp:127.0.0.1:" + std::to_string(port));
  const std::string epochs[] = {"$GPGGA,a*00\r\n$GPRMC,a*00\r\n", "$GPGGA,bb*00\r\n$GPRMC,bb*00\r\n",
                                std::string(4000, 'x')};
  for (const auto& e : epochs) ASSERT_EQ(out.write_epoch(e), WriteStatus::ok);
  for (const auto& e : epochs) EXPECT_EQ(receive_datagram(fd), e);
  EXPECT_EQ(out.stats().epochs_written, 3u);
  ::close(fd);
}

TEST(UdpOutputTest, NobodyListeningIsNotAnError) {
  auto [fd, port] = bind_receiver();
  ::close(fd);  // the port is free now: datagrams get ICMP port unreachable
  UdpOutput out("127.0.0.1", port);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(out.write_epoch("$GPGGA,x*00\r\n"), WriteStatus::ok) << i;
  EXPECT_EQ(out.stats().epochs_failed, 0u);
  // Written, but the summary says nobody was there (the kernel reports each refusal at the next send).
  EXPECT_GE(out.unreachable(), 10u);
  EXPECT_NE(out.clients_summary().find("datagrams reported unreachable (nobody was listening"), std::string::npos)
      << out.clients_summary();
}

TEST(UdpOutputTest, AListenerLeavesNoUnreachableInTheSummary) {
  auto [fd, port] = bind_receiver();
  UdpOutput out("127.0.0.1", port);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(out.write_epoch("$GPGGA,x*00\r\n"), WriteStatus::ok) << i;
  EXPECT_EQ(out.unreachable(), 0u);
  EXPECT_TRUE(out.clients_summary().empty()) << out.clients_summary();
  ::close(fd);
}

TEST(UdpOutputTest, SpecsParseAndErrorsNameTheHost) {
  const OutputSpec spec = parse_output_spec("udp:127.0.0.1:10110");
  EXPECT_EQ(spec.kind, OutputKind::udp);
  EXPECT_EQ(spec.host, "127.0.0.1");
  EXPECT_EQ(spec.port, 10110);
  EXPECT_EQ(to_string(spec), "udp:127.0.0.1:10110");
  EXPECT_EQ(to_string(parse_output_spec("udp:[::1]:10110")), "udp:[::1]:10110");
  for (const std::string bad : {"udp", "udp:", "udp:10110", "udp:127.0.0.1:0", "udp:127.0.0.1:x"}) {
    try {
      (void)parse_output_spec(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad + "'"), std::string::npos) << e.what();
    }
  }
  try {
    UdpOutput out("no-such-host.invalid", 10110);
    ADD_FAILURE() << "resolved";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-host.invalid"), std::string::npos) << e.what();
  }
}

}  // namespace udp_test
}  // namespace
}  // namespace gpsemu::transport
