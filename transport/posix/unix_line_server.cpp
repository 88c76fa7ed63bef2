#include "transport/posix/unix_line_server.hpp"

#include <algorithm>

#include <poll.h>
#include <sys/timerfd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include <functional>

#include "transport/posix/errors.hpp"
#include "transport/posix/sockets.hpp"

namespace gpsemu::posix {
namespace {

bool send_line_blocking(int fd, std::string_view text) {
  std::string line(text);
  line += '\n';
  std::size_t sent = 0;
  while (sent < line.size()) {
    const ssize_t n = ::send(fd, line.data() + sent, line.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

/// Whether a server answers on the Unix socket at `address` (false: a file nobody listens on, left
/// by a run that died). Throws `fail(...)` when it cannot tell.
bool someone_listens(const sockaddr_un& address, const std::function<std::runtime_error(const std::string&)>& fail) {
  UniqueFd probe(::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!probe.valid()) throw fail(errno_text(errno));
  if (::connect(probe.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0) return true;
  if (errno == EAGAIN || errno == EINPROGRESS) return true;  // listening, its backlog full
  if (errno == ECONNREFUSED || errno == ENOENT) return false;
  throw fail(fmt::format("exists and cannot be checked: {}; remove it or choose another path", errno_text(errno)));
}

}  // namespace

UnixLineServer::UnixLineServer(std::string path, Settings settings)
    : path_(std::move(path)), settings_(std::move(settings)), wake_(::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC)) {
  const auto fail = [this](const std::string& why) { return std::runtime_error(fmt::format("control socket {}: {}", path_, why)); };
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path_.empty() || path_.size() >= sizeof address.sun_path)
    throw fail(fmt::format("the path must have 1..{} characters", sizeof address.sun_path - 1));
  std::memcpy(address.sun_path, path_.data(), path_.size());
  struct stat st{};
  if (::lstat(path_.c_str(), &st) == 0) {
    if (!S_ISSOCK(st.st_mode)) throw fail("exists and is not a socket; remove it or choose another path");
    if (someone_listens(address, fail))
      throw fail("in use: another process answers on it (another gpsemu with the same --control?); stop it or choose another path");
    ::unlink(path_.c_str());  // a socket left by a run that died: nobody listens on it
  }
  listen_.reset(::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!listen_.valid()) throw fail(errno_text(errno));
  if (::bind(listen_.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) throw fail(errno_text(errno));
  if (::listen(listen_.get(), 8) != 0) {
    const int err = errno;
    ::unlink(path_.c_str());
    throw fail(errno_text(err));
  }
  if (::lstat(path_.c_str(), &st) == 0) {
    file_device_ = st.st_dev;
    file_inode_ = st.st_ino;
  }
}

UnixLineServer::UnixLineServer(UniqueFd listening, std::string name, Settings settings)
    : path_(std::move(name)), settings_(std::move(settings)), listen_(std::move(listening)), owns_file_(false),
      wake_(::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC)) {}

UnixLineServer::~UnixLineServer() {
  if (!listen_.valid() || !owns_file_) return;
  // Only the file we made: another process may have put its own there since.
  struct stat st{};
  if (::lstat(path_.c_str(), &st) == 0 && S_ISSOCK(st.st_mode) && st.st_dev == file_device_ && st.st_ino == file_inode_)
    ::unlink(path_.c_str());
}

void UnixLineServer::close_idle(std::chrono::steady_clock::time_point now) {
  if (settings_.idle_timeout <= std::chrono::milliseconds::zero()) return;
  std::erase_if(clients_, [&](const Client& c) {
    if (c.watch || now - c.last_line < settings_.idle_timeout) return false;
    (void)send_line(c.fd.get(), settings_.messages.idle_closed);
    ++stats_.clients_idle_closed;
    return true;
  });
}

void UnixLineServer::fds(std::vector<int>& out) const {
  out.push_back(listen_.get());
  if (wake_.valid()) out.push_back(wake_.get());
  for (const Client& c : clients_) out.push_back(c.fd.get());
}

bool UnixLineServer::send_line(int fd, std::string_view text) {
  std::string line(text);
  line += '\n';
  const ssize_t n = ::send(fd, line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  return n == static_cast<ssize_t>(line.size());
}

void UnixLineServer::service(const Handler& handle) {
  service(WatchHandler([&handle](std::string_view line, std::optional<std::int64_t>&) { return handle(line); }));
}

void UnixLineServer::push(std::string_view line, std::int64_t tag) {
  std::erase_if(clients_, [&](const Client& c) {
    if (!c.watch || (*c.watch != -1 && *c.watch != tag)) return false;
    if (send_line(c.fd.get(), line)) {
      ++stats_.lines_pushed;
      return false;
    }
    ++stats_.clients_not_reading;
    return true;
  });
}

std::size_t UnixLineServer::watchers() const {
  return static_cast<std::size_t>(std::count_if(clients_.begin(), clients_.end(), [](const Client& c) { return c.watch.has_value(); }));
}

bool UnixLineServer::make_room(std::chrono::steady_clock::time_point now) {
  // The client whose last request is oldest, if it is older than kEvictAfter (never a watcher):
  // clients that connect and say nothing (or only empty lines) cannot lock the operator out.
  auto oldest = clients_.end();
  for (auto it = clients_.begin(); it != clients_.end(); ++it) {
    if (!it->watch && now - it->last_line >= kEvictAfter && (oldest == clients_.end() || it->last_line < oldest->last_line)) {
      oldest = it;
    }
  }
  if (oldest == clients_.end()) return false;
  (void)send_line(oldest->fd.get(), settings_.messages.evicted);
  ++stats_.clients_evicted;
  clients_.erase(oldest);
  return true;
}

bool UnixLineServer::answer_pending(Client& c, const WatchHandler& handle, std::size_t& budget,
                                    std::chrono::steady_clock::time_point now) {
  while (budget > 0) {
    const std::size_t nl = c.pending.find('\n');
    if (nl == std::string::npos) {
      if (c.pending.size() > kMaxLineBytes) {
        // A line too long: told once, skipped to its end.
        if (!c.discarding) {
          ++stats_.lines_too_long;
          if (!send_line(c.fd.get(), settings_.messages.line_too_long)) {
            ++stats_.clients_not_reading;
            return false;
          }
        }
        c.discarding = true;
        c.pending.clear();
      }
      return true;
    }
    std::string line = c.pending.substr(0, nl);
    c.pending.erase(0, nl + 1);
    if (c.discarding) {  // the end of a line too long
      c.discarding = false;
      continue;
    }
    if (line.size() > kMaxLineBytes) {
      ++stats_.lines_too_long;
      if (!send_line(c.fd.get(), settings_.messages.line_too_long)) {
        ++stats_.clients_not_reading;
        return false;
      }
      continue;
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) {
      ++stats_.empty_lines;  // neither a request nor activity: an empty line keeps no client in
      continue;
    }
    c.last_line = now;
    --budget;
    ++stats_.lines_answered;
    if (!send_line(c.fd.get(), handle(line, c.watch))) {
      ++stats_.clients_not_reading;
      return false;
    }
  }
  return true;
}

void UnixLineServer::service(const WatchHandler& handle) {
  const auto now = std::chrono::steady_clock::now();
  if (wake_.valid()) {
    std::uint64_t count = 0;
    (void)!::read(wake_.get(), &count, sizeof count);
  }
  close_idle(now);
  while (true) {
    UniqueFd fd(::accept4(listen_.get(), nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC));
    if (!fd.valid()) break;
    if (clients_.size() >= kMaxClients && !make_room(now)) {
      (void)send_line(fd.get(), settings_.messages.too_many_clients);
      ++stats_.clients_refused;
      continue;
    }
    ++stats_.clients_accepted;
    Client client{std::move(fd), now, {}, false, std::nullopt};
    client.credit_at = now;
    clients_.push_back(std::move(client));
  }
  // Each client at most kLinesPerService answers a call and kLinesPerSecond on average (a burst of
  // kLinesBurst), read kReadBytes at a time: a client that pipelines requests as fast as it can is
  // answered between epochs, a few at a time, and never makes one late; what it sent beyond waits
  // in its buffer and its socket (its sends block: the kernel's back-pressure), and the loop comes
  // back when its budget allows (wake_).
  std::optional<std::chrono::steady_clock::duration> come_back;
  const auto again_in = [&come_back](std::chrono::steady_clock::duration d) {
    if (!come_back || d < *come_back) come_back = d;
  };
  char buffer[kReadBytes];
  for (auto it = clients_.begin(); it != clients_.end();) {
    Client& c = *it;
    const double elapsed_s = std::chrono::duration<double>(now - c.credit_at).count();
    c.credit = std::min(static_cast<double>(kLinesBurst), c.credit + elapsed_s * static_cast<double>(kLinesPerSecond));
    c.credit_at = now;
    std::size_t budget = std::min<std::size_t>(kLinesPerService, static_cast<std::size_t>(c.credit));
    const std::size_t given = budget;
    bool gone = !answer_pending(c, handle, budget, now);
    while (!gone && budget > 0) {
      const ssize_t n = ::recv(c.fd.get(), buffer, sizeof buffer, MSG_DONTWAIT);
      if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
        // Its end closed: a last line without '\n' is still a request (printf '...' | nc -U PATH).
        if (n == 0 && !c.discarding && c.pending.find('\n') == std::string::npos && !c.pending.empty()) c.pending += '\n';
        if (n == 0) (void)answer_pending(c, handle, budget, now);
        if (n == 0 && c.pending.find('\n') != std::string::npos) {
          c.closed_by_peer = true;  // lines left: answered at the next calls, then closed
          break;
        }
        gone = true;
        break;
      }
      if (n < 0) break;
      c.pending.append(buffer, static_cast<std::size_t>(n));
      gone = !answer_pending(c, handle, budget, now);
    }
    c.credit -= static_cast<double>(given - budget);
    if (!gone && c.closed_by_peer && c.pending.find('\n') == std::string::npos) gone = true;
    if (!gone && budget == 0) {
      // More may wait: at once while its rate allows, else when a line's credit is back.
      if (c.credit >= 1.0) {
        again_in(std::chrono::microseconds(1));
      } else {
        if (!c.throttled) ++stats_.clients_throttled;
        c.throttled = true;
        again_in(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>((1.0 - c.credit) / static_cast<double>(kLinesPerSecond))));
      }
    } else if (!gone) {
      c.throttled = false;
    }
    if (gone) {
      it = clients_.erase(it);
    } else {
      ++it;
    }
  }
  if (come_back && wake_.valid()) {
    const auto ns = std::max<std::int64_t>(1, std::chrono::duration_cast<std::chrono::nanoseconds>(*come_back).count());
    itimerspec once{};
    once.it_value.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
    once.it_value.tv_nsec = static_cast<long>(ns % 1'000'000'000);
    (void)::timerfd_settime(wake_.get(), 0, &once, nullptr);
  }
}

namespace {

/// Sends `line` on the connected `fd` and gives `sink` each line of the answer until it returns
/// false (a line not followed by another within `timeout` fails; so does a close before the first).
void exchange(int fd, std::string_view line, std::chrono::milliseconds timeout,
              const std::function<std::runtime_error(const std::string&)>& fail, const LineSink& sink) {
  if (!send_line_blocking(fd, line)) throw fail(fmt::format("cannot send: {}", errno_text(errno)));
  std::string pending;
  bool first = true;
  char buffer[4096];
  for (;;) {
    for (std::size_t nl = pending.find('\n'); nl != std::string::npos; nl = pending.find('\n')) {
      const std::string text = pending.substr(0, nl);
      pending.erase(0, nl + 1);
      first = false;
      if (!sink(text)) return;
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(timeout.count()));
    if (ready < 0 && errno == EINTR) continue;
    if (ready == 0) throw fail(first ? "no answer" : fmt::format("nothing more for {} ms", timeout.count()));
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (first) throw fail("closed without an answer");
      return;
    }
    pending.append(buffer, static_cast<std::size_t>(n));
  }
}

/// The first line of the answer.
LineSink first_line(std::string& out) {
  return [&out](std::string_view text) {
    out = text;
    return false;
  };
}

}  // namespace

std::string unix_request(const std::string& path, std::string_view line, std::chrono::milliseconds timeout) {
  std::string answer;
  unix_exchange(path, line, timeout, first_line(answer));
  return answer;
}

std::string tcp_request(const std::string& host, std::uint16_t port, std::string_view line,
                        std::chrono::milliseconds timeout) {
  std::string answer;
  tcp_exchange(host, port, line, timeout, first_line(answer));
  return answer;
}

void unix_exchange(const std::string& path, std::string_view line, std::chrono::milliseconds timeout, const LineSink& sink) {
  const std::function<std::runtime_error(const std::string&)> fail = [&path](const std::string& why) {
    return std::runtime_error(fmt::format("control socket {}: {}", path, why));
  };
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof address.sun_path) throw fail("path too long");
  std::memcpy(address.sun_path, path.data(), path.size());
  UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!fd.valid()) throw fail(errno_text(errno));
  if (::connect(fd.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0)
    throw fail(fmt::format("cannot connect: {} (is gpsemu running with --control unix:{}?)", errno_text(errno), path));
  exchange(fd.get(), line, timeout, fail, sink);
}

void tcp_exchange(const std::string& host, std::uint16_t port, std::string_view line, std::chrono::milliseconds timeout,
                  const LineSink& sink) {
  const std::string name = "tcp:" + host_port(host, port);
  const std::function<std::runtime_error(const std::string&)> fail = [&name](const std::string& why) {
    return std::runtime_error(fmt::format("control socket {}: {}", name, why));
  };
  SocketRequest request;
  request.host = host;
  request.port = port;
  request.passive = false;
  request.blocking = true;
  request.context = fmt::format("control socket {}: cannot connect (is gpsemu running with --control {}?)", name, name);
  UniqueFd fd = connect_socket(request);
  exchange(fd.get(), line, timeout, fail, sink);
}

}  // namespace gpsemu::posix
