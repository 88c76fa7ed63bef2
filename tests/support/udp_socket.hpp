// A UDP socket bound on loopback at a port the kernel chose, for the tests that read gpsemu's UDP
// outputs; one socket option (a receive buffer, kernel time stamps) may be set on it, and the
// datagrams waiting can be read with the kernel's receive time stamps (SO_TIMESTAMPNS). Also a
// fleet's sinks and the configuration tables that send each receiver to its own.
#pragma once

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

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

  /// A datagram and the kernel's receive time (seconds of the UTC day; `stamped` false when the
  /// socket was not asked for SO_TIMESTAMPNS).
  struct Stamped {
    std::string bytes;
    bool stamped = false;
    double seconds_of_day = 0.0;
  };
  /// Every datagram waiting now, in order, without blocking.
  std::vector<Stamped> drain_stamped() const {
    std::vector<Stamped> got;
    for (;;) {
      char data[2048];
      char control[256];
      iovec iov{data, sizeof data};
      msghdr msg{};
      msg.msg_iov = &iov;
      msg.msg_iovlen = 1;
      msg.msg_control = control;
      msg.msg_controllen = sizeof control;
      const ssize_t n = ::recvmsg(fd, &msg, MSG_DONTWAIT);
      if (n <= 0) return got;
      timespec stamp{};
      for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) std::memcpy(&stamp, CMSG_DATA(c), sizeof stamp);
      }
      got.push_back({std::string(data, static_cast<std::size_t>(n)), stamp.tv_sec != 0,
                     static_cast<double>(stamp.tv_sec % 86400) + static_cast<double>(stamp.tv_nsec) * 1e-9});
    }
  }

  int fd = -1;
  std::uint16_t port = 0;
};

/// `count` sockets asking for the kernel's receive time stamps (SO_TIMESTAMPNS): a fleet's sinks.
inline std::vector<std::unique_ptr<LoopbackUdpSocket>> stamped_sinks(int count) {
  std::vector<std::unique_ptr<LoopbackUdpSocket>> sinks;
  for (int i = 0; i < count; ++i) sinks.push_back(std::make_unique<LoopbackUdpSocket>(SO_TIMESTAMPNS, 1));
  return sinks;
}

/// The `[[receiver]]` tables of a fleet configuration that send receiver i's output to sinks[i]
/// (pointers to anything with a loopback `port`).
template <class Sinks>
std::string receivers_writing_to(const Sinks& sinks) {
  std::string toml;
  for (const auto& sink : sinks) toml += "[[receiver]]\noutput = \"udp:127.0.0.1:" + std::to_string(sink->port) + "\"\n";
  return toml;
}

}  // namespace gpsemu::test
