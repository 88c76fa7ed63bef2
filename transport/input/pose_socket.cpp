#include "transport/input/pose_socket.hpp"

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "transport/posix/sockets.hpp"
#include "transport/posix/tcp_server.hpp"
#include "transport/posix/wall_clock.hpp"

namespace gpsemu::transport {
namespace {

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

std::string where(const char* scheme, const PoseEndpoint& endpoint) {
  return fmt::format("cannot listen on {}:{}", scheme, posix::host_port(endpoint.host, endpoint.port));
}

// ---------------------------------------------------------------------------------------------

class UdpPoseSocket final : public PoseSocket {
 public:
  UdpPoseSocket(const PoseEndpoint& endpoint, const PoseSocketOptions& options)
      : endpoint_(endpoint), buffer_(options.max_message_bytes + 1), max_(options.max_message_bytes) {
    fd_ = posix::bind_socket({.host = endpoint.host, .port = endpoint.port, .type = SOCK_DGRAM,
                              .context = where("udp", endpoint)},
                             // kernel arrival time (CLOCK_REALTIME) and the count of datagrams it dropped
                             [](int fd) { (void)posix::enable_datagram_stamps(fd); });
    endpoint_.port = posix::bound_port(fd_.get());
  }

  std::optional<ReceivedMessage> receive() override {
    if (unreported_drops_ > 0) {
      ReceivedMessage m;
      m.kind = ReceivedMessage::Kind::kernel_dropped;
      m.count = unreported_drops_;
      m.arrival = posix::wall_clock_now();
      unreported_drops_ = 0;
      return m;
    }
    const auto d = posix::receive_datagram(fd_.get(), buffer_);
    if (!d) return std::nullopt;  // EAGAIN, or an error the next call will see again
    ReceivedMessage m;
    m.arrival = d->kernel_time ? *d->kernel_time : posix::wall_clock_now();
    if (d->drop_counter) unreported_drops_ += drops_.update(*d->drop_counter);
    m.sender = address_id(d->from);
    m.sender_name = std::string_view(name_.data(), posix::format_address(d->from, name_));
    if (d->size > max_) {
      m.kind = ReceivedMessage::Kind::too_large;
    } else {
      m.bytes = std::string_view(buffer_.data(), d->size);
    }
    return m;
  }

  int poll_fd() const override { return fd_.get(); }
  std::string describe() const override { return "udp:" + posix::host_port(endpoint_.host, endpoint_.port); }
  std::uint16_t port() const override { return endpoint_.port; }

 private:
  PoseEndpoint endpoint_;
  posix::UniqueFd fd_;
  std::vector<char> buffer_;
  std::size_t max_;
  std::array<char, 64> name_{};
  posix::DropCounter drops_;
  std::uint64_t unreported_drops_ = 0;
};

// ---------------------------------------------------------------------------------------------

class TcpPoseServer final : public PoseSocket {
 public:
  TcpPoseServer(const PoseEndpoint& endpoint, const PoseSocketOptions& options)
      : endpoint_(endpoint),
        max_(options.max_message_bytes),
        idle_timeout_(options.idle_timeout),
        take_over_idle_(options.take_over_idle),
        server_(endpoint.host, endpoint.port, where("tcp", endpoint),
                {.max_clients = options.max_clients, .take_over = [this] { return idlest_client(); }}),
        clients_(options.max_clients) {
    endpoint_.port = server_.port();
    for (auto& c : clients_) c.buffer.resize(max_ + 2);  // a longest line, CR, LF; allocated once per slot
  }

  std::optional<ReceivedMessage> receive() override {
    if (pending_connect_) {  // the newcomer that took over a slot, reported after the client it closed
      const std::size_t slot = *pending_connect_;
      pending_connect_.reset();
      return event(ReceivedMessage::Kind::connected, clients_[slot]);
    }
    for (int step = 0; step < 8; ++step) {
      if (current_) {
        if (auto m = next_from_client(*current_)) return m;
        current_.reset();
      }
      const auto event = server_.next_event();
      if (!event) return close_idle_client();
      using Kind = posix::TcpServerEvent::Kind;
      if (event->kind == Kind::ready) {
        read_client(event->slot);
        current_ = event->slot;
        continue;
      }
      Client& c = event->kind == Kind::connected ? clients_[event->slot] : refused_;
      if (event->replaced != 0) {  // keep the closed client's name for its report
        taken_over_.serial = c.serial;
        taken_over_.name = c.name;
        taken_over_.name_len = c.name_len;
        taken_over_.arrival = posix::wall_clock_now();
      }
      c.serial = event->serial;
      c.arrival = c.last_line = posix::wall_clock_now();
      const auto r = fmt::format_to_n(c.name.data(), c.name.size() - 1, "{} (tcp #{})", event->peer, event->serial);
      c.name_len = std::min(r.size, c.name.size() - 1);
      if (event->kind == Kind::refused) return this->event(ReceivedMessage::Kind::refused_client, c);
      c.start = c.end = 0;
      c.discarding = c.eof = false;
      if (event->replaced != 0) {
        pending_connect_ = event->slot;
        return this->event(ReceivedMessage::Kind::taken_over, taken_over_);
      }
      return this->event(ReceivedMessage::Kind::connected, c);
    }
    return std::nullopt;
  }

  int poll_fd() const override { return server_.poll_fd(); }
  std::string describe() const override { return "tcp:" + posix::host_port(endpoint_.host, endpoint_.port); }
  std::uint16_t port() const override { return endpoint_.port; }

 private:
  static constexpr std::uint64_t kTcpBit = 1ull << 63;

  /// What a connection has sent that was not returned yet.
  struct Client {
    std::uint64_t serial = 0;
    std::array<char, 96> name{};
    std::size_t name_len = 0;
    std::vector<char> buffer;        ///< max_message_bytes + 2 (room for CR LF)
    std::size_t start = 0, end = 0;  ///< unread bytes are buffer[start, end)
    bool discarding = false;         ///< inside an overlong line: drop bytes up to the next '\n'
    bool eof = false;
    posix::WallTime arrival{};
    posix::WallTime last_line{};     ///< when its last complete line was read (or it connected)
  };

  /// Every slot taken: the client without a complete line for longest, if for take_over_idle.
  std::optional<std::size_t> idlest_client() const {
    const posix::WallTime now = posix::wall_clock_now();
    std::optional<std::size_t> idlest;
    for (std::size_t i = 0; i < clients_.size(); ++i) {
      if (!server_.occupied(i) || clients_[i].eof || now - clients_[i].last_line < take_over_idle_) continue;
      if (!idlest || clients_[i].last_line < clients_[*idlest].last_line) idlest = i;
    }
    return idlest;
  }

  /// Closes one client without a complete line for the idle timeout (a few compares and one
  /// clock read a call, only while clients are connected).
  std::optional<ReceivedMessage> close_idle_client() {
    if (server_.client_count() == 0) return std::nullopt;
    const posix::WallTime now = posix::wall_clock_now();
    for (std::size_t i = 0; i < clients_.size(); ++i) {
      Client& c = clients_[i];
      if (!server_.occupied(i) || c.eof || now - c.last_line < idle_timeout_) continue;
      c.arrival = now;
      ReceivedMessage m = event(ReceivedMessage::Kind::idle_closed, c);
      server_.drop(i);
      c.start = c.end = 0;
      c.discarding = false;
      return m;  // sender_name points into the slot, untouched until the next accept
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

  void read_client(std::size_t slot) {
    Client& c = clients_[slot];
    if (c.eof) return;
    if (c.start > 0) {  // compact: the previously returned line is no longer referenced
      std::memmove(c.buffer.data(), c.buffer.data() + c.start, c.end - c.start);
      c.end -= c.start;
      c.start = 0;
    }
    const ssize_t n = ::read(server_.client_fd(slot), c.buffer.data() + c.end, c.buffer.size() - c.end);
    c.arrival = posix::wall_clock_now();
    if (n > 0) {
      c.end += static_cast<std::size_t>(n);
    } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      c.eof = true;
      server_.watch(slot, false, false);  // its lines are returned first, then it is dropped
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
      c.last_line = c.arrival;
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
    server_.drop(slot);
    c.start = c.end = 0;
    c.eof = c.discarding = false;
    current_.reset();
    return m;  // sender_name points into the slot, untouched until the next accept
  }

  PoseEndpoint endpoint_;
  std::size_t max_;
  std::chrono::nanoseconds idle_timeout_, take_over_idle_;
  posix::TcpServer server_;
  std::vector<Client> clients_;
  Client refused_, taken_over_;  ///< names for the reports of a refused and a closed client
  std::optional<std::size_t> current_;
  std::optional<std::size_t> pending_connect_;
};

}  // namespace

std::unique_ptr<PoseSocket> open_udp_pose_socket(const PoseEndpoint& endpoint, const PoseSocketOptions& options) {
  return std::make_unique<UdpPoseSocket>(endpoint, options);
}

std::unique_ptr<PoseSocket> open_tcp_pose_server(const PoseEndpoint& endpoint, const PoseSocketOptions& options) {
  return std::make_unique<TcpPoseServer>(endpoint, options);
}

}  // namespace gpsemu::transport
