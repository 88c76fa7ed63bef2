#include "transport/udp_output.hpp"

#include <spdlog/spdlog.h>
#include <sys/socket.h>

#include <cerrno>
#include <stdexcept>

#include "transport/posix/errors.hpp"
#include "transport/posix/sockets.hpp"

namespace gpsemu::transport {

UdpOutput::UdpOutput(const std::string& host, std::uint16_t port)
    : description_("udp:" + posix::host_port(host, port)) {
  if (port == 0) throw std::runtime_error(fmt::format("udp output {}: the destination port must not be 0", description_));
  // Connected: the route is looked up once, not on every send (a fleet sends hundreds of
  // datagrams at each deadline). connect() on UDP sends nothing.
  fd_ = posix::connect_socket({.host = host, .port = port, .type = SOCK_DGRAM,
                               .context = "udp output " + description_, .failure = "cannot open a socket: "},
                              [](int fd) {
                                const int one = 1;
                                (void)::setsockopt(fd, SOL_SOCKET, SO_BROADCAST, &one, sizeof one);
                              });
  spdlog::info("udp output: sending to {}", description_);
}

WriteStatus UdpOutput::write_bytes(std::string_view bytes, std::string& error_text) {
  for (int refused = 0;;) {
    const ssize_t n = ::send(fd_.get(), bytes.data(), bytes.size(), MSG_DONTWAIT);
    if (n >= 0 && static_cast<std::size_t>(n) == bytes.size()) return WriteStatus::ok;
    if (n < 0 && errno == EINTR) continue;
    // An ICMP "port unreachable" for an earlier datagram (nobody was listening) is reported by
    // the next send on a connected socket, which then sends nothing: send again, so a listener
    // that has just started gets this epoch. A missing listener is never an error (UDP).
    if (n < 0 && errno == ECONNREFUSED) {
      ++unreachable_;  // an earlier datagram found nobody listening
      if (++refused < 2) continue;
      return WriteStatus::ok;
    }
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS)) {
      error_text = "the kernel's send buffer is full";
      return WriteStatus::dropped;
    }
    error_text = n < 0 ? fmt::format("sendto failed: {}", posix::errno_text(errno))
                       : fmt::format("sent only {} of {} bytes", n, bytes.size());
    return WriteStatus::error;
  }
}

std::string UdpOutput::clients_summary() const {
  if (unreachable_ == 0) return {};
  return fmt::format("; {} datagrams reported unreachable (nobody was listening on the port then)", unreachable_);
}

}  // namespace gpsemu::transport
