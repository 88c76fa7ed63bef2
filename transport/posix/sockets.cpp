#include "transport/posix/sockets.hpp"

#include <dirent.h>
#include <sys/resource.h>

#include <arpa/inet.h>
#include <linux/tcp.h>
#include <netinet/in.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cstddef>
#include <cstring>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "transport/posix/errors.hpp"

namespace gpsemu::posix {
namespace {

std::string socket_error_text(int err) {
  return err == EADDRINUSE ? "the port is in use by another program" : errno_text(err);
}

}  // namespace

std::size_t format_address(const sockaddr_storage& address, std::span<char> out) {
  if (out.empty()) return 0;
  char ip[INET6_ADDRSTRLEN] = "?";
  fmt::format_to_n_result<char*> r{};
  if (address.ss_family == AF_INET) {
    const auto* a = reinterpret_cast<const sockaddr_in*>(&address);
    inet_ntop(AF_INET, &a->sin_addr, ip, sizeof ip);
    r = fmt::format_to_n(out.data(), out.size(), "{}:{}", ip, ntohs(a->sin_port));
  } else if (address.ss_family == AF_INET6) {
    const auto* a = reinterpret_cast<const sockaddr_in6*>(&address);
    inet_ntop(AF_INET6, &a->sin6_addr, ip, sizeof ip);
    r = fmt::format_to_n(out.data(), out.size(), "[{}]:{}", ip, ntohs(a->sin6_port));
  } else {
    r = fmt::format_to_n(out.data(), out.size(), "?");
  }
  return std::min(r.size, out.size());
}

std::string address_text(const sockaddr_storage& address) {
  std::array<char, INET6_ADDRSTRLEN + 8> text{};
  return std::string(text.data(), format_address(address, text));
}

std::uint16_t bound_port(int fd) {
  sockaddr_storage address{};
  socklen_t len = sizeof address;
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &len) != 0) return 0;
  if (address.ss_family == AF_INET) return ntohs(reinterpret_cast<const sockaddr_in*>(&address)->sin_port);
  if (address.ss_family == AF_INET6) return ntohs(reinterpret_cast<const sockaddr_in6*>(&address)->sin6_port);
  return 0;
}

namespace {

/// The peer of a connected TCP socket (not a listening one, not another kind), if `fd` is one bound to `port`.
std::optional<std::string> tcp_peer_on_port(int fd, std::uint16_t port) {
  int type = 0, listening = 0;
  socklen_t len = sizeof type;
  if (::getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &len) != 0 || type != SOCK_STREAM) return std::nullopt;
  len = sizeof listening;
  if (::getsockopt(fd, SOL_SOCKET, SO_ACCEPTCONN, &listening, &len) != 0 || listening != 0) return std::nullopt;
  if (bound_port(fd) != port) return std::nullopt;
  sockaddr_storage peer{};
  len = sizeof peer;
  if (::getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &len) != 0) return std::nullopt;
  return address_text(peer);
}

}  // namespace

std::optional<std::uint32_t> tcp_unsent_bytes(int fd) {
  tcp_info info{};
  socklen_t len = sizeof info;
  if (::getsockopt(fd, IPPROTO_TCP, TCP_INFO, &info, &len) != 0) return std::nullopt;
  if (len < offsetof(tcp_info, tcpi_notsent_bytes) + sizeof info.tcpi_notsent_bytes) return std::nullopt;  // an older kernel
  return info.tcpi_notsent_bytes;
}

std::vector<AcceptedConnection> connections_on_port(std::uint16_t port) {
  std::vector<AcceptedConnection> out;
  DIR* dir = ::opendir("/proc/self/fd");
  if (dir == nullptr) return out;
  const int own = ::dirfd(dir);
  while (const dirent* entry = ::readdir(dir)) {
    int fd = -1;
    const std::string_view name(entry->d_name);
    const auto [end, ec] = std::from_chars(name.data(), name.data() + name.size(), fd);
    if (ec != std::errc() || end != name.data() + name.size() || fd == own) continue;
    if (std::optional<std::string> peer = tcp_peer_on_port(fd, port)) out.push_back({fd, std::move(*peer)});
  }
  ::closedir(dir);
  return out;
}

bool shut_down_connection(int fd, std::string_view peer) {
  sockaddr_storage now{};
  socklen_t len = sizeof now;
  if (::getpeername(fd, reinterpret_cast<sockaddr*>(&now), &len) != 0 || address_text(now) != peer) return false;
  return ::shutdown(fd, SHUT_RDWR) == 0;
}

UniqueFd open_socket(const SocketRequest& request, const SocketSetup& setup) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = request.type;
  hints.ai_flags = AI_NUMERICSERV | (request.passive ? AI_PASSIVE : 0);
  addrinfo* found = nullptr;
  const std::string port = std::to_string(request.port);
  const char* host = request.host.empty() ? nullptr : request.host.c_str();
  if (const int rc = ::getaddrinfo(host, port.c_str(), &hints, &found); rc != 0) {
    throw std::runtime_error(fmt::format("{}: host '{}': {}", request.context, request.host, gai_strerror(rc)));
  }
  const int flags = SOCK_CLOEXEC | (request.blocking ? 0 : SOCK_NONBLOCK);
  std::string last_error = "no address";
  for (const addrinfo* ai = found; ai != nullptr; ai = ai->ai_next) {
    UniqueFd fd(::socket(ai->ai_family, ai->ai_socktype | flags, ai->ai_protocol));
    if (!fd.valid()) {
      last_error = errno_text(errno);
      continue;
    }
    if (const int err = setup(fd.get(), *ai); err != 0) {
      last_error = socket_error_text(err);
      continue;
    }
    ::freeaddrinfo(found);
    return fd;
  }
  ::freeaddrinfo(found);
  throw std::runtime_error(fmt::format("{}: {}{}", request.context, request.failure, last_error));
}

UniqueFd listen_tcp(const SocketRequest& request, int backlog) {
  SocketRequest tcp = request;
  tcp.type = SOCK_STREAM;
  tcp.passive = true;
  return open_socket(tcp, [backlog](int fd, const addrinfo& ai) {
    const int on = 1;
    (void)::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    return ::bind(fd, ai.ai_addr, ai.ai_addrlen) == 0 && ::listen(fd, backlog) == 0 ? 0 : errno;
  });
}

UniqueFd bind_socket(const SocketRequest& request, const std::function<void(int fd)>& configure) {
  SocketRequest bound = request;
  bound.passive = true;
  return open_socket(bound, [&configure](int fd, const addrinfo& ai) {
    if (configure) configure(fd);
    return ::bind(fd, ai.ai_addr, ai.ai_addrlen) == 0 ? 0 : errno;
  });
}

UniqueFd connect_socket(const SocketRequest& request, const std::function<void(int fd)>& configure) {
  SocketRequest connected = request;
  connected.passive = false;
  return open_socket(connected, [&configure](int fd, const addrinfo& ai) {
    if (configure) configure(fd);
    return ::connect(fd, ai.ai_addr, ai.ai_addrlen) == 0 ? 0 : errno;
  });
}

int enable_datagram_stamps(int fd) {
  const int on = 1;
  const int err = ::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) == 0 ? 0 : errno;
  (void)::setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on);
  return err;
}

std::optional<Datagram> receive_datagram(int fd, std::span<char> buffer) {
  Datagram d;
  iovec iov{buffer.data(), buffer.size()};
  alignas(cmsghdr) std::array<char, 256> control{};
  msghdr msg{};
  msg.msg_name = &d.from;
  msg.msg_namelen = sizeof d.from;
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control.data();
  msg.msg_controllen = control.size();
  const ssize_t n = ::recvmsg(fd, &msg, MSG_DONTWAIT | MSG_TRUNC);
  if (n < 0) return std::nullopt;
  d.size = static_cast<std::size_t>(n);
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level != SOL_SOCKET) continue;
    if (c->cmsg_type == SCM_TIMESTAMPNS) {
      timespec ts{};
      std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
      d.kernel_time = to_wall_time(ts);
    } else if (c->cmsg_type == SO_RXQ_OVFL) {
      std::uint32_t counter = 0;
      std::memcpy(&counter, CMSG_DATA(c), sizeof counter);
      d.drop_counter = counter;
    }
  }
  return d;
}

void configure_listening_socket(int fd, int send_buffer_bytes) {
  const int yes = 1;
  (void)::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  (void)::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &send_buffer_bytes, sizeof send_buffer_bytes);
}

void set_listen_backlog(int fd, int backlog) { (void)::listen(fd, backlog); }

std::uint64_t raise_open_files_limit() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) return 0;
  if (limit.rlim_cur < limit.rlim_max) {
    limit.rlim_cur = limit.rlim_max;
    (void)::setrlimit(RLIMIT_NOFILE, &limit);
    (void)::getrlimit(RLIMIT_NOFILE, &limit);
  }
  return static_cast<std::uint64_t>(limit.rlim_cur);
}

}  // namespace gpsemu::posix
