#include "transport/tcp_output.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <spdlog/spdlog.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace gpsemu::transport {

namespace {

std::string errno_text(int err) { return std::generic_category().message(err); }

constexpr int kMaxEventsPerService = 64;     ///< bounds one service() call
constexpr int kMaxAcceptsPerService = 16;    ///< bounds one service() call
constexpr std::size_t kMaxInputPerClient = 64 * 1024;  ///< bytes read and dropped per client per call

std::string address_text(const sockaddr_storage& addr) {
  char ip[INET6_ADDRSTRLEN] = "?";
  if (addr.ss_family == AF_INET) {
    const auto* a = reinterpret_cast<const sockaddr_in*>(&addr);
    inet_ntop(AF_INET, &a->sin_addr, ip, sizeof ip);
    return fmt::format("{}:{}", ip, ntohs(a->sin_port));
  }
  if (addr.ss_family == AF_INET6) {
    const auto* a = reinterpret_cast<const sockaddr_in6*>(&addr);
    inet_ntop(AF_INET6, &a->sin6_addr, ip, sizeof ip);
    return fmt::format("[{}]:{}", ip, ntohs(a->sin6_port));
  }
  return "?";
}

}  // namespace

TcpOutput::TcpOutput(const std::string& host, std::uint16_t port, TcpOutputOptions options) : options_(options) {
  const std::string where = host.find(':') != std::string::npos ? fmt::format("tcp:[{}]:{}", host, port)
                                                                 : fmt::format("tcp:{}:{}", host, port);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const std::string port_text = std::to_string(port);
  if (const int rc = getaddrinfo(host.c_str(), port_text.c_str(), &hints, &found); rc != 0) {
    throw std::runtime_error(fmt::format("tcp output: cannot listen on {}: host '{}': {}", where, host, gai_strerror(rc)));
  }
  std::string last_error = "no address";
  for (const addrinfo* ai = found; ai != nullptr && listen_fd_ < 0; ai = ai->ai_next) {
    const int fd = ::socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol);
    if (fd < 0) {
      last_error = errno_text(errno);
      continue;
    }
    const int one = 1;
    (void)::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(fd, ai->ai_addr, ai->ai_addrlen) != 0 || ::listen(fd, 16) != 0) {
      last_error = errno == EADDRINUSE ? "the port is in use by another program" : errno_text(errno);
      ::close(fd);
      continue;
    }
    listen_fd_ = fd;
  }
  freeaddrinfo(found);
  if (listen_fd_ < 0) throw std::runtime_error(fmt::format("tcp output: cannot listen on {}: {}", where, last_error));

  sockaddr_storage bound{};
  socklen_t len = sizeof bound;
  ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound), &len);
  port_ = bound.ss_family == AF_INET6 ? ntohs(reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port)
                                      : ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
  description_ = "tcp:" + address_text(bound);

  epoll_fd_ = ::epoll_create1(EPOLL_CLOEXEC);
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.u64 = 0;
  if (epoll_fd_ < 0 || ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, listen_fd_, &ev) != 0) {
    const std::string why = errno_text(errno);
    ::close(listen_fd_);
    if (epoll_fd_ >= 0) ::close(epoll_fd_);
    throw std::runtime_error(fmt::format("tcp output {}: epoll: {}", description_, why));
  }
  spdlog::info("tcp output: listening on {}", description_);
}

TcpOutput::~TcpOutput() {
  for (auto& [id, client] : clients_) ::close(client.fd);
  ::close(listen_fd_);
  ::close(epoll_fd_);
}

void TcpOutput::accept_clients() {
  for (int i = 0; i < kMaxAcceptsPerService; ++i) {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    const int fd = ::accept4(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EINTR || errno == ECONNABORTED) continue;
      return;  // EAGAIN: none waiting; EMFILE and the like: try again next time
    }
    if (clients_.size() >= options_.max_clients) {
      ++tcp_stats_.clients_refused;
      ::close(fd);
      spdlog::warn("{}: refused client {}: already {} clients", description_, address_text(addr), clients_.size());
      continue;
    }
    const int one = 1;
    (void)::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);  // an epoch goes out at once
    if (options_.socket_send_buffer_bytes > 0) {
      (void)::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &options_.socket_send_buffer_bytes,
                         sizeof options_.socket_send_buffer_bytes);
    }
    const std::uint64_t id = next_id_++;
    epoll_event ev{};
    ev.events = EPOLLIN | EPOLLRDHUP;
    ev.data.u64 = id;
    if (::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, fd, &ev) != 0) {
      ::close(fd);
      continue;
    }
    clients_.emplace(id, Client{fd, address_text(addr), {}, false});
    ++tcp_stats_.clients_accepted;
    spdlog::info("{}: client {} connected ({} now)", description_, address_text(addr), clients_.size());
  }
}

void TcpOutput::close_client(std::uint64_t id, const char* why) {
  const auto it = clients_.find(id);
  if (it == clients_.end()) return;
  (void)::epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, it->second.fd, nullptr);
  ::close(it->second.fd);
  spdlog::debug("{}: client {} {}", description_, it->second.name, why);
  clients_.erase(it);
}

bool TcpOutput::send_pending(std::uint64_t id, Client& client) {
  std::size_t done = 0;
  while (done < client.pending.size()) {
    const ssize_t n = ::send(client.fd, client.pending.data() + done, client.pending.size() - done,
                             MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    return false;
  }
  client.pending.erase(0, done);
  update_interest(id, client);
  return true;
}

void TcpOutput::update_interest(std::uint64_t id, Client& client) {
  const bool want_out = !client.pending.empty();
  if (want_out == client.want_out) return;
  epoll_event ev{};
  ev.events = EPOLLIN | EPOLLRDHUP | (want_out ? EPOLLOUT : 0u);
  ev.data.u64 = id;
  (void)::epoll_ctl(epoll_fd_, EPOLL_CTL_MOD, client.fd, &ev);
  client.want_out = want_out;
}

WriteStatus TcpOutput::write_bytes(std::string_view bytes, std::string& error_text) {
  std::vector<std::uint64_t> failed;
  std::vector<std::uint64_t> slow;
  for (auto& [id, client] : clients_) {
    if (!client.pending.empty() && client.pending.size() + bytes.size() > options_.client_buffer_bytes) {
      slow.push_back(id);
      continue;
    }
    client.pending.append(bytes);
    if (!send_pending(id, client)) failed.push_back(id);
  }
  for (const auto id : slow) {
    ++tcp_stats_.clients_dropped_slow;
    close_client(id, "disconnected: too slow (its buffer is full)");
  }
  for (const auto id : failed) {
    ++tcp_stats_.clients_closed;
    close_client(id, "closed (send failed)");
  }
  report_drops();
  (void)error_text;
  return WriteStatus::ok;
}

void TcpOutput::service() {
  std::array<epoll_event, kMaxEventsPerService> events{};
  const int n = ::epoll_wait(epoll_fd_, events.data(), static_cast<int>(events.size()), 0);
  for (int i = 0; i < n; ++i) {
    const std::uint64_t id = events[static_cast<std::size_t>(i)].data.u64;
    const std::uint32_t what = events[static_cast<std::size_t>(i)].events;
    if (id == 0) {
      accept_clients();
      continue;
    }
    const auto it = clients_.find(id);
    if (it == clients_.end()) continue;
    Client& client = it->second;
    bool closed = (what & EPOLLERR) != 0;
    if (!closed && (what & (EPOLLIN | EPOLLRDHUP | EPOLLHUP))) {
      std::array<char, 4096> buf{};
      std::size_t got = 0;
      while (got < kMaxInputPerClient) {
        const ssize_t r = ::recv(client.fd, buf.data(), buf.size(), MSG_DONTWAIT);
        if (r > 0) {
          got += static_cast<std::size_t>(r);
          tcp_stats_.input_bytes_discarded += static_cast<std::uint64_t>(r);
          client_wrote({buf.data(), static_cast<std::size_t>(r)});
          continue;
        }
        if (r < 0 && errno == EINTR) continue;
        if (r < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
        closed = true;  // 0: the client closed; otherwise reset
        break;
      }
    }
    if (!closed && (what & EPOLLOUT)) closed = !send_pending(id, client);
    if (closed) {
      ++tcp_stats_.clients_closed;
      close_client(id, "closed the connection");
    }
  }
  report_drops();
}

void TcpOutput::report_drops() {
  if (tcp_stats_.clients_dropped_slow == reported_.clients_dropped_slow) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_report_ < std::chrono::seconds(1)) return;
  spdlog::warn("{}: disconnected {} client(s) too slow to keep up (more than {} bytes waiting); {} connected",
               description_, tcp_stats_.clients_dropped_slow - reported_.clients_dropped_slow,
               options_.client_buffer_bytes, clients_.size());
  reported_ = tcp_stats_;
  last_report_ = now;
}

}  // namespace gpsemu::transport
