// Sockets of the POSIX layer on loopback: a bound UDP socket receives datagrams with the kernel's
// arrival stamp, whole length and sender; a connect that is refused names host:port.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <array>
#include <chrono>
#include <stdexcept>
#include <string>

#include "transport/posix/sockets.hpp"
#include "transport/posix/wall_clock.hpp"

namespace gpsemu::posix {
namespace {
namespace sockets_test {

TEST(Sockets, AUdpDatagramArrivesWithKernelStampLengthAndSender) {
  const UniqueFd rx = bind_socket({.host = "127.0.0.1", .port = 0, .type = SOCK_DGRAM, .context = "rx"},
                                  [](int fd) { ASSERT_EQ(enable_datagram_stamps(fd), 0); });
  const std::uint16_t port = bound_port(rx.get());
  ASSERT_NE(port, 0);
  const UniqueFd tx = connect_socket({.host = "127.0.0.1", .port = port, .type = SOCK_DGRAM, .context = "tx"});
  std::array<char, 8> buffer{};
  EXPECT_FALSE(receive_datagram(rx.get(), buffer));  // nothing yet: never blocks
  const WallTime before = wall_clock_now();
  ASSERT_EQ(::send(tx.get(), "0123456789", 10, 0), 10);
  pollfd pfd{rx.get(), POLLIN, 0};
  ASSERT_EQ(::poll(&pfd, 1, 3000), 1);
  const auto d = receive_datagram(rx.get(), buffer);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->size, 10u);  // its whole length, though only 8 bytes fit
  EXPECT_EQ(std::string(buffer.data(), buffer.size()), "01234567");
  ASSERT_TRUE(d->kernel_time);
  EXPECT_GE(*d->kernel_time, before);
  EXPECT_LE(*d->kernel_time, wall_clock_now());
  EXPECT_EQ(address_text(d->from), "127.0.0.1:" + std::to_string(bound_port(tx.get())));
}

TEST(Sockets, ARefusedConnectNamesHostAndPort) {
  std::uint16_t port = 0;
  {
    const UniqueFd probe = listen_tcp({.host = "127.0.0.1", .port = 0, .context = "probe"});
    port = bound_port(probe.get());
  }  // closed: nobody listens there now
  const std::string where = host_port("127.0.0.1", port);
  try {
    (void)connect_socket({.host = "127.0.0.1", .port = port, .blocking = true, .context = "cannot connect to " + where});
    FAIL() << "connected to a closed port";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "cannot connect to " + where + ": Connection refused");
  }
}

}  // namespace sockets_test
}  // namespace
}  // namespace gpsemu::posix
