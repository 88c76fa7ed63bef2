#include "transport/tcp_output.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>

#include <cerrno>
#include <utility>

#include "transport/posix/sockets.hpp"

namespace gpsemu::transport {

namespace {

constexpr int kMaxEventsPerService = 64;               ///< bounds one service() call

}  // namespace

TcpOutput::TcpOutput(const std::string& host, std::uint16_t port, TcpOutputOptions options)
    : options_(options),
      server_(host, port, "tcp output: cannot listen on tcp:" + posix::host_port(host, port),
              {.max_clients = options.max_clients, .no_delay = true,  // an epoch goes out at once
               .send_buffer_bytes = options.socket_send_buffer_bytes, .take_over = [this] { return most_behind(); }}),
      description_("tcp:" + server_.address()),
      pending_(options.max_clients),
      ids_(options.max_clients, 0),
      connected_at_(options.max_clients) {
  spdlog::info("tcp output: listening on {}", description_);
}

std::optional<std::size_t> TcpOutput::most_behind() const {
  // Every slot taken: a newcomer takes the place of the client most behind (bytes waiting for it
  // here and in its socket), the oldest of those equally behind, among those connected for
  // kTakeOverAfter at least; so clients that connect and never read cannot keep a reader out,
  // and the one that came last is the last to go.
  const auto now = std::chrono::steady_clock::now();
  std::optional<std::size_t> best;
  std::pair<std::uint64_t, std::int64_t> best_score{};
  for (std::size_t slot = 0; slot < server_.slots(); ++slot) {
    if (!server_.occupied(slot) || now - connected_at_[slot] < kTakeOverAfter) continue;
    std::uint64_t behind = pending_[slot].size();
    behind += posix::tcp_unsent_bytes(server_.client_fd(slot)).value_or(0);
    const std::pair<std::uint64_t, std::int64_t> score{behind, -connected_at_[slot].time_since_epoch().count()};
    if (!best || score > best_score) {
      best = slot;
      best_score = score;
    }
  }
  return best;
}

void TcpOutput::close_client(std::size_t slot, const char* why) {
  spdlog::debug("{}: client {} {}", description_, server_.peer(slot), why);
  server_.drop(slot);
  pending_[slot].clear();
  client_left(ids_[slot]);  // a half-written frame is not the next connection's
  ids_[slot] = 0;
}

bool TcpOutput::send_pending(std::size_t slot) {
  std::string& pending = pending_[slot];
  const int fd = server_.client_fd(slot);
  std::size_t done = 0;
  while (done < pending.size()) {
    const ssize_t n = ::send(fd, pending.data() + done, pending.size() - done, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    return false;
  }
  pending.erase(0, done);
  server_.watch(slot, true, !pending.empty());
  return true;
}

WriteStatus TcpOutput::write_bytes(std::string_view bytes, std::string& error_text) {
  failed_.clear();
  slow_.clear();
  if (server_.client_count() == 0) ++tcp_stats_.epochs_to_nobody;
  for (std::size_t slot = 0; slot < server_.slots(); ++slot) {
    if (!server_.occupied(slot)) continue;
    std::string& pending = pending_[slot];
    if (!pending.empty() && pending.size() + bytes.size() > options_.client_buffer_bytes) {
      slow_.push_back(slot);
      continue;
    }
    pending.append(bytes);
    if (!send_pending(slot)) failed_.push_back(slot);
  }
  for (const auto slot : slow_) {
    ++tcp_stats_.clients_dropped_slow;
    close_client(slot, "disconnected: too slow (its buffer is full)");
  }
  for (const auto slot : failed_) {
    ++tcp_stats_.clients_closed;
    close_client(slot, "closed (send failed)");
  }
  report_drops();
  (void)error_text;
  return WriteStatus::ok;
}

WriteStatus TcpOutput::write_reply(ClientId client, std::string_view bytes, std::string& error_text) {
  for (std::size_t slot = 0; slot < server_.slots(); ++slot) {
    if (!server_.occupied(slot) || ids_[slot] != client) continue;
    std::string& pending = pending_[slot];
    if (pending.size() + bytes.size() > options_.client_buffer_bytes) {
      error_text = "no room in the client's buffer";
      return WriteStatus::dropped;
    }
    pending.append(bytes);  // behind the whole epochs queued for it
    if (!send_pending(slot)) {
      ++tcp_stats_.clients_closed;
      close_client(slot, "closed (send failed)");
    }
    return WriteStatus::ok;
  }
  error_text = "its client disconnected";
  return WriteStatus::dropped;
}

void TcpOutput::service() {
  for (int i = 0; i < kMaxEventsPerService; ++i) {
    const auto event = server_.next_event();
    if (!event) break;
    handle(*event);
  }
  report_drops();
}

void TcpOutput::handle(const posix::TcpServerEvent& event) {
  using Kind = posix::TcpServerEvent::Kind;
  if (event.kind == Kind::refused) {
    ++tcp_stats_.clients_refused;
    log_limited(refused_log_, spdlog::level::warn, "{}: refused client {}: already {} clients", description_, event.peer,
                server_.client_count());
    return;
  }
  if (event.kind == Kind::connected) {
    if (event.replaced != 0) {
      ++tcp_stats_.clients_replaced;
      log_limited(refused_log_, spdlog::level::warn, "{}: client {} took the place of one {} s old and most behind "
                  "(every one of {} slots taken)", description_, event.peer,
                  std::chrono::duration_cast<std::chrono::seconds>(kTakeOverAfter).count(), server_.slots());
    }
    connected_at_[event.slot] = std::chrono::steady_clock::now();
    pending_[event.slot].clear();
    ids_[event.slot] = new_client_id();
    ++tcp_stats_.clients_accepted;
    log_limited(connect_log_, spdlog::level::info, "{}: client {} connected ({} now)", description_, event.peer,
                server_.client_count());
    return;
  }
  bool closed = false;
  if (event.readable) {
    std::uint64_t read_bytes = 0;  // taken by the receiver; the rest is discarded
    const posix::Drained input = posix::drain_input(
        server_.client_fd(event.slot), client_input_budget, [this, &read_bytes, id = ids_[event.slot]](std::string_view bytes) {
          if (client_wrote(bytes, id)) read_bytes += bytes.size();
        });
    tcp_stats_.input_bytes_discarded += input.bytes - read_bytes;
    closed = input.end != posix::Drained::End::empty;  // 0: the client closed; otherwise reset
  }
  if (!closed && event.writable) closed = !send_pending(event.slot);
  if (closed) {
    ++tcp_stats_.clients_closed;
    close_client(event.slot, "closed the connection");
  }
}

std::string TcpOutput::clients_summary() const {
  const TcpStats& t = tcp_stats_;
  return fmt::format("; clients: {} connected, {} refused (every slot taken), {} closed for a newcomer (most behind), "
                     "{} dropped too slow, {} closed; {} of the epochs written had no client to go to",
                     t.clients_accepted, t.clients_refused, t.clients_replaced, t.clients_dropped_slow, t.clients_closed,
                     t.epochs_to_nobody);
}

void TcpOutput::report_drops() {
  if (tcp_stats_.clients_dropped_slow == reported_.clients_dropped_slow) return;
  if (log_limited(drop_log_, spdlog::level::warn,
                  "{}: disconnected {} client(s) too slow to keep up (more than {} bytes waiting); {} connected",
                  description_, tcp_stats_.clients_dropped_slow - reported_.clients_dropped_slow,
                  options_.client_buffer_bytes, server_.client_count())) {
    reported_ = tcp_stats_;
  }
}

}  // namespace gpsemu::transport
