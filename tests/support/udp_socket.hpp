// A UDP socket bound on loopback at a port the kernel chose, for the tests that read gpsemu's UDP
// outputs; one socket option (a receive buffer, kernel time stamps) may be set on it.
#pragma once

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>

namespace gpsemu::test {

struct LoopbackUdpSocket {
  /// Bound to 127.0.0.1:0; `option` (SOL_SOCKET level, e.g. SO_RCVBUF) set to `value` unless 0.
  explicit LoopbackUdpSocket(int option = 0, int value = 0) {
    fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    (void)::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    port = ntohs(a.sin_port);
    if (option != 0) ::setsockopt(fd, SOL_SOCKET, option, &value, sizeof value);
  }
  ~LoopbackUdpSocket() { ::close(fd); }
  LoopbackUdpSocket(const LoopbackUdpSocket&) = delete;
  LoopbackUdpSocket& operator=(const LoopbackUdpSocket&) = delete;

  int fd = -1;
  std::uint16_t port = 0;
};

}  // namespace gpsemu::test
