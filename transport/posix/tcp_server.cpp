#include "transport/posix/tcp_server.hpp"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <cerrno>
#include <stdexcept>

#include <fmt/format.h>

#include "transport/posix/errors.hpp"
#include "transport/posix/sockets.hpp"

namespace gpsemu::posix {
namespace {

// epoll data: 0 is the listening socket; a client is (serial << 20) | (slot + 1), so an event
// still queued for a client that has gone is not taken for the next client in its slot.
constexpr std::uint64_t kListenTag = 0;
constexpr int kSlotBits = 20;

std::uint64_t tag_of(std::uint64_t serial, std::size_t slot) { return (serial << kSlotBits) | (slot + 1); }

}  // namespace

TcpServer::TcpServer(const std::string& host, std::uint16_t port, const std::string& context,
                     TcpServerOptions options)
    : options_(options), clients_(options.max_clients) {
  if (options.max_clients >= (std::size_t{1} << kSlotBits) - 1) {
    throw std::invalid_argument(fmt::format("{}: at most {} clients", context, (1 << kSlotBits) - 2));
  }
  listen_ = listen_tcp({.host = host, .port = port, .context = context});
  port_ = bound_port(listen_.get());
  sockaddr_storage bound{};
  socklen_t len = sizeof bound;
  ::getsockname(listen_.get(), reinterpret_cast<sockaddr*>(&bound), &len);
  address_ = address_text(bound);
  epoll_ = UniqueFd(::epoll_create1(EPOLL_CLOEXEC));
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.u64 = kListenTag;
  if (!epoll_.valid() || ::epoll_ctl(epoll_.get(), EPOLL_CTL_ADD, listen_.get(), &ev) != 0) {
    throw std::runtime_error(fmt::format("{}: epoll: {}", context, errno_text(errno)));
  }
}

std::optional<TcpServerEvent> TcpServer::next_event() {
  for (bool waited = false;;) {
    while (next_event_ < event_count_) {
      const epoll_event ev = events_[static_cast<std::size_t>(next_event_++)];
      if (ev.data.u64 == kListenTag) {
        if (auto accepted = accept_one()) return accepted;
        continue;
      }
      const std::size_t slot = (ev.data.u64 & ((std::uint64_t{1} << kSlotBits) - 1)) - 1;
      if (slot >= clients_.size() || clients_[slot].serial != ev.data.u64 >> kSlotBits) continue;  // gone
      const Client& c = clients_[slot];
      TcpServerEvent e;
      e.kind = TcpServerEvent::Kind::ready;
      e.slot = slot;
      e.serial = c.serial;
      e.peer = std::string_view(c.peer.data(), c.peer_len);
      e.readable = (ev.events & (EPOLLIN | EPOLLRDHUP | EPOLLHUP | EPOLLERR)) != 0;
      e.writable = (ev.events & EPOLLOUT) != 0;
      return e;
    }
    if (waited) return std::nullopt;
    waited = true;
    event_count_ = ::epoll_wait(epoll_.get(), events_.data(), static_cast<int>(events_.size()), 0);
    next_event_ = 0;
    if (event_count_ <= 0) {
      event_count_ = 0;
      return std::nullopt;
    }
  }
}

std::optional<TcpServerEvent> TcpServer::accept_one() {
  sockaddr_storage from{};
  socklen_t len = sizeof from;
  UniqueFd fd(::accept4(listen_.get(), reinterpret_cast<sockaddr*>(&from), &len, SOCK_NONBLOCK | SOCK_CLOEXEC));
  if (!fd.valid()) return std::nullopt;  // EAGAIN: none waiting; EMFILE and the like: try again next time
  std::optional<std::size_t> slot;
  for (std::size_t i = 0; i < clients_.size() && !slot; ++i) {
    if (clients_[i].serial == 0) slot = i;
  }
  std::uint64_t replaced = 0;
  if (!slot && options_.take_over) {
    slot = options_.take_over();
    if (slot && (*slot >= clients_.size() || clients_[*slot].serial == 0)) slot.reset();
    if (slot) {
      replaced = clients_[*slot].serial;
      drop(*slot);
    }
  }
  Client& c = slot ? clients_[*slot] : refused_;
  c.serial = ++serial_counter_;
  c.peer_len = format_address(from, c.peer);
  TcpServerEvent e;
  e.serial = c.serial;
  e.peer = std::string_view(c.peer.data(), c.peer_len);
  if (!slot) {
    e.kind = TcpServerEvent::Kind::refused;
    return e;  // fd closes here
  }
  const int one = 1;
  if (options_.no_delay) (void)::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  if (options_.send_buffer_bytes > 0) {
    (void)::setsockopt(fd.get(), SOL_SOCKET, SO_SNDBUF, &options_.send_buffer_bytes, sizeof options_.send_buffer_bytes);
  }
  c.fd = std::move(fd);
  c.read = c.write = false;
  watch(*slot, true, false);
  if (!c.read) {  // epoll refused it: as if it had never connected
    c.fd.reset();
    c.serial = 0;
    return std::nullopt;
  }
  ++client_count_;
  e.kind = TcpServerEvent::Kind::connected;
  e.slot = *slot;
  e.replaced = replaced;
  return e;
}

void TcpServer::watch(std::size_t slot, bool read, bool write) {
  Client& c = clients_[slot];
  if (!c.fd.valid() || (read == c.read && write == c.write)) return;
  const bool was_watched = c.read || c.write;
  if (!read && !write) {
    (void)::epoll_ctl(epoll_.get(), EPOLL_CTL_DEL, c.fd.get(), nullptr);
  } else {
    epoll_event ev{};
    ev.events = (read ? EPOLLIN | EPOLLRDHUP : 0u) | (write ? EPOLLOUT : 0u);
    ev.data.u64 = tag_of(c.serial, slot);
    if (::epoll_ctl(epoll_.get(), was_watched ? EPOLL_CTL_MOD : EPOLL_CTL_ADD, c.fd.get(), &ev) != 0) return;
  }
  c.read = read;
  c.write = write;
}

void TcpServer::drop(std::size_t slot) {
  Client& c = clients_[slot];
  if (c.serial == 0) return;
  watch(slot, false, false);
  c.fd.reset();
  c.serial = 0;
  --client_count_;
}

}  // namespace gpsemu::posix
