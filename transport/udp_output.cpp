#include "transport/udp_output.hpp"

#include <netdb.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace gpsemu::transport {

namespace {

std::string errno_text(int err) { return std::generic_category().message(err); }

}  // namespace

UdpOutput::UdpOutput(const std::string& host, std::uint16_t port) {
  description_ = host.find(':') != std::string::npos ? fmt::format("udp:[{}]:{}", host, port)
                                                     : fmt::format("udp:{}:{}", host, port);
  if (port == 0) throw std::runtime_error(fmt::format("udp output {}: the destination port must not be 0", description_));
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_flags = AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const std::string port_text = std::to_string(port);
  if (const int rc = getaddrinfo(host.c_str(), port_text.c_str(), &hints, &found); rc != 0) {
    throw std::runtime_error(fmt::format("udp output {}: host '{}': {}", description_, host, gai_strerror(rc)));
  }
  std::string last_error = "no address";
  for (const addrinfo* ai = found; ai != nullptr && fd_ < 0; ai = ai->ai_next) {
    const int fd = ::socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol);
    if (fd < 0) {
      last_error = errno_text(errno);
      continue;
    }
    const int one = 1;
    (void)::setsockopt(fd, SOL_SOCKET, SO_BROADCAST, &one, sizeof one);
    std::memcpy(&destination_, ai->ai_addr, ai->ai_addrlen);
    destination_len_ = ai->ai_addrlen;
    // Connected: the route is looked up once, not on every send (a fleet sends hundreds of
    // datagrams at each deadline). connect() on UDP sends nothing.
    if (::connect(fd, ai->ai_addr, ai->ai_addrlen) != 0) {
      last_error = errno_text(errno);
      ::close(fd);
      continue;
    }
    fd_ = fd;
  }
  freeaddrinfo(found);
  if (fd_ < 0) throw std::runtime_error(fmt::format("udp output {}: cannot open a socket: {}", description_, last_error));
  spdlog::info("udp output: sending to {}", description_);
}

UdpOutput::~UdpOutput() { ::close(fd_); }

WriteStatus UdpOutput::write_bytes(std::string_view bytes, std::string& error_text) {
  for (int refused = 0;;) {
    const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_DONTWAIT);
    if (n >= 0 && static_cast<std::size_t>(n) == bytes.size()) return WriteStatus::ok;
    if (n < 0 && errno == EINTR) continue;
    // An ICMP "port unreachable" for an earlier datagram (nobody was listening) is reported by
    // the next send on a connected socket, which then sends nothing: send again, so a listener
    // that has just started gets this epoch. A missing listener is never an error (UDP).
    if (n < 0 && errno == ECONNREFUSED) {
      if (++refused < 2) continue;
      return WriteStatus::ok;
    }
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS)) {
      error_text = "the kernel's send buffer is full";
      return WriteStatus::dropped;
    }
    error_text = n < 0 ? fmt::format("sendto failed: {}", errno_text(errno))
                       : fmt::format("sent only {} of {} bytes", n, bytes.size());
    return WriteStatus::error;
  }
}

}  // namespace gpsemu::transport
