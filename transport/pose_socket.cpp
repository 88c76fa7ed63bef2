#include "transport/pose_socket.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace gpsemu::transport {
namespace {

using SysNs = std::chrono::sys_time<std::chrono::nanoseconds>;

SysNs realtime_now() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return SysNs{std::chrono::nanoseconds{static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec}};
}

std::string host_port(const std::string& host, std::uint16_t port) {
  return host.find(':') != std::string::npos ? fmt::format("[{}]:{}", host, port) : fmt::format("{}:{}", host, port);
}

/// "203.0.113.5:50123" or "[::1]:50123" into `out`; returns its length.
std::size_t format_address(const sockaddr_storage& addr, char* out, std::size_t size) {
  char ip[INET6_ADDRSTRLEN] = "?";
  unsigned port = 0;
  bool v6 = false;
  if (addr.ss_family == AF_INET) {
    const auto* a = reinterpret_cast<const sockaddr_in*>(&addr);
    inet_ntop(AF_INET, &a->sin_addr, ip, sizeof ip);
    port = ntohs(a->sin_port);
  } else if (addr.ss_family == AF_INET6) {
    const auto* a = reinterpret_cast<const sockaddr_in6*>(&addr);
    inet_ntop(AF_INET6, &a->sin6_addr, ip, sizeof ip);
    port = ntohs(a->sin6_port);
    v6 = true;
  }
  const auto r = v6 ? fmt::format_to_n(out, size - 1, "[{}]:{}", ip, port)
                    : fmt::format_to_n(out, size - 1, "{}:{}", ip, port);
  return r.size < size ? r.size : size - 1;
}

/// FNV-1a over the address family, address and port: the identity of a UDP sender.
std::uint64_t address_id(const sockaddr_storage& addr) {
  const unsigned char* p = reinterpret_cast<const unsigned char*>(&addr);
  std::size_t n = 0;
  if (addr.ss_family == AF_INET) n = sizeof(sockaddr_in);
  if (addr.ss_family == AF_INET6) n = sizeof(sockaddr_in6);
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < n; ++i) {
    // sin_zero and sin6_flowinfo/scope vary per datagram on some stacks: hash family, port, address only.
    if (addr.ss_family == AF_INET && i >= offsetof(sockaddr_in, sin_zero)) break;
    if (addr.ss_family == AF_INET6 && i >= offsetof(sockaddr_in6, sin6_flowinfo) &&
        i < offsetof(sockaddr_in6, sin6_addr)) continue;
    if (addr.ss_family == AF_INET6 && i >= offsetof(sockaddr_in6, sin6_scope_id)) break;
    h = (h ^ p[i]) * 1099511628211ull;
  }
  return h & ~(1ull << 63);  // TCP connections use the top bit
}

class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  ~Fd() { reset(); }
  Fd(Fd&& o) noexcept : fd_(o.fd_) { o.fd_ = -1; }
  Fd& operator=(Fd&& o) noexcept {
    if (this != &o) {
      reset();
      fd_ = o.fd_;
      o.fd_ = -1;
    }
    return *this;
  }
  void reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  [[nodiscard]] int get() const { return fd_; }

 private:
  int fd_;
};

/// Creates, configures and binds a socket of `type` on the endpoint. Throws std::runtime_error.
template <class Configure>
Fd bind_socket(const PoseEndpoint& endpoint, int type, const char* scheme, Configure configure) {
  const std::string where = fmt::format("{}:{}", scheme, host_port(endpoint.host, endpoint.port));
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = type;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(endpoint.port);
  if (const int rc = getaddrinfo(endpoint.host.c_str(), port.c_str(), &hints, &found); rc != 0) {
    throw std::runtime_error(fmt::format("cannot listen on {}: host '{}': {}", where, endpoint.host, gai_strerror(rc)));
  }
  std::string last_error = "no address";
  for (const addrinfo* ai = found; ai != nullptr; ai = ai->ai_next) {
    Fd fd(::socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol));
    if (fd.get() < 0) {
      last_error = std::strerror(errno);
      continue;
    }
    configure(fd.get());
    if (::bind(fd.get(), ai->ai_addr, ai->ai_addrlen) != 0) {
      last_error = std::strerror(errno);
      continue;
    }
    freeaddrinfo(found);
    return fd;
  }
  freeaddrinfo(found);
  throw std::runtime_error(fmt::format("cannot listen on {}: {}", where, last_error));
}

std::uint16_t bound_port(int fd) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  if (addr.ss_family == AF_INET) return ntohs(reinterpret_cast<sockaddr_in*>(&addr)->sin_port);
  if (addr.ss_family == AF_INET6) return ntohs(reinterpret_cast<sockaddr_in6*>(&addr)->sin6_port);
  return 0;
}

// ---------------------------------------------------------------------------------------------

class UdpPoseSocket final : public PoseSocket {
 public:
  UdpPoseSocket(const PoseEndpoint& endpoint, const PoseSocketOptions& options)
      : endpoint_(endpoint), buffer_(options.max_message_bytes + 1), max_(options.max_message_bytes) {
    fd_ = bind_socket(endpoint, SOCK_DGRAM, "udp", [](int fd) {
      const int on = 1;
      setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on);  // kernel arrival time, CLOCK_REALTIME
      setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on);     // count of datagrams the kernel dropped
    });
    endpoint_.port = bound_port(fd_.get());
  }

  std::optional<ReceivedMessage> receive() override {
    if (unreported_drops_ > 0) {
      ReceivedMessage m;
      m.kind = ReceivedMessage::Kind::kernel_dropped;
      m.count = unreported_drops_;
      m.arrival = realtime_now();
      unreported_drops_ = 0;
      return m;
    }
    sockaddr_storage from{};
    iovec iov{buffer_.data(), buffer_.size()};
    alignas(cmsghdr) std::array<char, 256> control{};
    msghdr msg{};
    msg.msg_name = &from;
    msg.msg_namelen = sizeof from;
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control.data();
    msg.msg_controllen = control.size();
    const ssize_t n = ::recvmsg(fd_.get(), &msg, MSG_DONTWAIT | MSG_TRUNC);
    if (n < 0) return std::nullopt;  // EAGAIN, or an error the next call will see again

    ReceivedMessage m;
    m.arrival = realtime_now();
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level != SOL_SOCKET) continue;
      if (c->cmsg_type == SCM_TIMESTAMPNS) {
        timespec ts{};
        std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
        m.arrival = SysNs{std::chrono::nanoseconds{static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec}};
      } else if (c->cmsg_type == SO_RXQ_OVFL) {
        std::uint32_t dropped = 0;
        std::memcpy(&dropped, CMSG_DATA(c), sizeof dropped);
        unreported_drops_ += static_cast<std::uint32_t>(dropped - kernel_drops_seen_);
        kernel_drops_seen_ = dropped;
      }
    }
    m.sender = address_id(from);
    m.sender_name = std::string_view(name_.data(), format_address(from, name_.data(), name_.size()));
    if (static_cast<std::size_t>(n) > max_) {
      m.kind = ReceivedMessage::Kind::too_large;
    } else {
      m.bytes = std::string_view(buffer_.data(), static_cast<std::size_t>(n));
    }
    return m;
  }

  int poll_fd() const override { return fd_.get(); }
  std::string describe() const override { return "udp:" + host_port(endpoint_.host, endpoint_.port); }
  std::uint16_t port() const override { return endpoint_.port; }

 private:
  PoseEndpoint endpoint_;
  Fd fd_;
  std::vector<char> buffer_;
  std::size_t max_;
  std::array<char, 64> name_{};
  std::uint32_t kernel_drops_seen_ = 0;
  std::uint64_t unreported_drops_ = 0;
};

// ---------------------------------------------------------------------------------------------

class TcpPoseServer final : public PoseSocket {
 public:
  TcpPoseServer(const PoseEndpoint& endpoint, const PoseSocketOptions& options)
      : endpoint_(endpoint), max_(options.max_message_bytes), clients_(options.max_clients) {
    listen_ = bind_socket(endpoint, SOCK_STREAM, "tcp", [](int fd) {
      const int on = 1;
      setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);  // restart while old connections linger
    });
    if (::listen(listen_.get(), 16) != 0) {
      throw std::runtime_error(fmt::format("cannot listen on tcp:{}: {}", host_port(endpoint.host, endpoint.port),
                                           std::strerror(errno)));
    }
    endpoint_.port = bound_port(listen_.get());
    epoll_ = Fd(epoll_create1(EPOLL_CLOEXEC));
    if (epoll_.get() < 0) throw std::runtime_error(fmt::format("epoll_create1: {}", std::strerror(errno)));
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.u64 = kListenTag;
    epoll_ctl(epoll_.get(), EPOLL_CTL_ADD, listen_.get(), &ev);
    for (auto& c : clients_) c.buffer.resize(max_ + 2);  // a longest line, CR, LF; allocated once per slot
  }

  std::optional<ReceivedMessage> receive() override {
    bool waited = false;
    for (int step = 0; step < 8; ++step) {
      if (current_) {
        if (auto m = next_from_client(*current_)) return m;
        current_.reset();
      }
      if (next_event_ < event_count_) {
        const epoll_event ev = events_[static_cast<std::size_t>(next_event_++)];
        if (ev.data.u64 == kListenTag) return accept_one();
        if (const auto slot = slot_of(ev.data.u64)) {
          read_client(*slot);
          current_ = slot;
        }
        continue;
      }
      if (waited) return std::nullopt;
      waited = true;
      event_count_ = epoll_wait(epoll_.get(), events_.data(), static_cast<int>(events_.size()), 0);
      next_event_ = 0;
      if (event_count_ <= 0) {
        event_count_ = 0;
        return std::nullopt;
      }
    }
    return std::nullopt;
  }

  int poll_fd() const override { return epoll_.get(); }
  std::string describe() const override { return "tcp:" + host_port(endpoint_.host, endpoint_.port); }
  std::uint16_t port() const override { return endpoint_.port; }

 private:
  static constexpr std::uint64_t kListenTag = 0;
  static constexpr std::uint64_t kTcpBit = 1ull << 63;

  struct Client {
    Fd fd;
    std::uint64_t serial = 0;   ///< 0: free slot
    std::array<char, 96> name{};
    std::size_t name_len = 0;
    std::vector<char> buffer;   ///< max_message_bytes + 2 (room for CR LF)
    std::size_t start = 0, end = 0;  ///< unread bytes are buffer[start, end)
    bool discarding = false;    ///< inside an overlong line: drop bytes up to the next '\n'
    bool eof = false;
    SysNs arrival{};
  };

  std::optional<std::size_t> slot_of(std::uint64_t serial) const {
    for (std::size_t i = 0; i < clients_.size(); ++i) {
      if (clients_[i].serial == serial) return i;
    }
    return std::nullopt;
  }

  ReceivedMessage event(ReceivedMessage::Kind kind, const Client& c) const {
    ReceivedMessage m;
    m.kind = kind;
    m.sender = c.serial | kTcpBit;
    m.sender_name = std::string_view(c.name.data(), c.name_len);
    m.arrival = c.arrival;
    return m;
  }

  std::optional<ReceivedMessage> accept_one() {
    sockaddr_storage from{};
    socklen_t len = sizeof from;
    Fd fd(::accept4(listen_.get(), reinterpret_cast<sockaddr*>(&from), &len, SOCK_NONBLOCK | SOCK_CLOEXEC));
    if (fd.get() < 0) return std::nullopt;
    const std::uint64_t serial = ++serial_counter_;
    const auto slot = slot_of(0);
    Client& c = slot ? clients_[*slot] : refused_;
    c.serial = serial;
    c.arrival = realtime_now();
    char addr[64];
    const std::size_t n = format_address(from, addr, sizeof addr);
    const auto r = fmt::format_to_n(c.name.data(), c.name.size() - 1, "{} (tcp #{})", std::string_view(addr, n), serial);
    c.name_len = std::min(r.size, c.name.size() - 1);
    if (!slot) return event(ReceivedMessage::Kind::refused_client, c);  // fd closes here
    c.fd = std::move(fd);
    c.start = c.end = 0;
    c.discarding = c.eof = false;
    epoll_event ev{};
    ev.events = EPOLLIN | EPOLLRDHUP;
    ev.data.u64 = serial;
    epoll_ctl(epoll_.get(), EPOLL_CTL_ADD, c.fd.get(), &ev);
    return event(ReceivedMessage::Kind::connected, c);
  }

  void read_client(std::size_t slot) {
    Client& c = clients_[slot];
    if (c.eof) return;
    if (c.start > 0) {  // compact: the previously returned line is no longer referenced
      std::memmove(c.buffer.data(), c.buffer.data() + c.start, c.end - c.start);
      c.end -= c.start;
      c.start = 0;
    }
    const ssize_t n = ::read(c.fd.get(), c.buffer.data() + c.end, c.buffer.size() - c.end);
    c.arrival = realtime_now();
    if (n > 0) {
      c.end += static_cast<std::size_t>(n);
    } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      c.eof = true;
      epoll_ctl(epoll_.get(), EPOLL_CTL_DEL, c.fd.get(), nullptr);
    }
  }

  std::optional<ReceivedMessage> next_from_client(std::size_t slot) {
    Client& c = clients_[slot];
    while (c.start < c.end) {
      const char* begin = c.buffer.data() + c.start;
      const auto* nl = static_cast<const char*>(std::memchr(begin, '\n', c.end - c.start));
      if (nl == nullptr) break;
      const std::size_t length = static_cast<std::size_t>(nl - begin);
      c.start += length + 1;
      if (c.discarding) {  // the tail of an overlong line
        c.discarding = false;
        continue;
      }
      std::size_t used = length;
      if (used > 0 && begin[used - 1] == '\r') --used;
      if (used == 0) continue;  // blank lines are keep-alives
      if (used > max_) return event(ReceivedMessage::Kind::too_large, c);
      ReceivedMessage m = event(ReceivedMessage::Kind::message, c);
      m.bytes = std::string_view(begin, used);
      return m;
    }
    if (c.end - c.start >= c.buffer.size()) {  // a full buffer without '\n': an overlong line
      c.start = c.end;
      if (!c.discarding) {
        c.discarding = true;
        return event(ReceivedMessage::Kind::too_large, c);
      }
    }
    if (!c.eof) return std::nullopt;
    if (c.end > c.start && !c.discarding) {
      c.start = c.end;
      return event(ReceivedMessage::Kind::partial_line, c);
    }
    ReceivedMessage m = event(ReceivedMessage::Kind::disconnected, c);
    c.fd.reset();
    c.serial = 0;
    c.start = c.end = 0;
    c.eof = c.discarding = false;
    current_.reset();
    return m;  // sender_name points into the slot, untouched until the next accept
  }

  PoseEndpoint endpoint_;
  std::size_t max_;
  Fd listen_, epoll_;
  std::vector<Client> clients_;
  Client refused_;
  std::uint64_t serial_counter_ = 0;
  std::array<epoll_event, 16> events_{};
  int event_count_ = 0, next_event_ = 0;
  std::optional<std::size_t> current_;
};

}  // namespace

PoseEndpoint parse_pose_endpoint(std::string_view text) {
  const auto bad = [&](const char* why) {
    return std::invalid_argument(fmt::format("'{}' is not [HOST:]PORT: {}", text, why));
  };
  PoseEndpoint e;
  std::string_view port = text;
  if (!text.empty() && text.front() == '[') {
    const auto close = text.find(']');
    if (close == std::string_view::npos || close + 1 >= text.size() || text[close + 1] != ':') {
      throw bad("an IPv6 host is written [ADDRESS]:PORT");
    }
    e.host = std::string(text.substr(1, close - 1));
    port = text.substr(close + 2);
  } else if (const auto colon = text.rfind(':'); colon != std::string_view::npos) {
    if (text.find(':') != colon) throw bad("an IPv6 host is written [ADDRESS]:PORT");
    e.host = std::string(text.substr(0, colon));
    port = text.substr(colon + 1);
  }
  if (e.host.empty()) throw bad("empty host");
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (port.empty() || ec != std::errc{} || end != port.data() + port.size() || value > 65535) {
    throw bad("the port must be a number from 0 to 65535");
  }
  e.port = static_cast<std::uint16_t>(value);
  return e;
}

std::unique_ptr<PoseSocket> open_udp_pose_socket(const PoseEndpoint& endpoint, const PoseSocketOptions& options) {
  return std::make_unique<UdpPoseSocket>(endpoint, options);
}

std::unique_ptr<PoseSocket> open_tcp_pose_server(const PoseEndpoint& endpoint, const PoseSocketOptions& options) {
  return std::make_unique<TcpPoseServer>(endpoint, options);
}

}  // namespace gpsemu::transport
