#include "emulator/ui/request_deadline.hpp"

#include "transport/posix/sockets.hpp"

namespace gpsemu::ui {

using Clock = std::chrono::steady_clock;

RequestDeadline::RequestDeadline(std::uint16_t port, std::chrono::milliseconds deadline)
    : port_(port), deadline_(deadline), thread_([this] { run(); }) {}

RequestDeadline::~RequestDeadline() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  stop_wait_.notify_all();
  thread_.join();
}

void RequestDeadline::begun(const std::string& peer) {
  std::lock_guard lock(mutex_);
  Connection& c = connections_[peer];
  c.answering = true;
}

bool RequestDeadline::claim_ended() {
  std::uint64_t n = unclaimed_.load(std::memory_order_relaxed);
  while (n > 0 && !unclaimed_.compare_exchange_weak(n, n - 1, std::memory_order_relaxed)) {
  }
  return n > 0;
}

bool RequestDeadline::done(const std::string& peer) {
  std::unique_lock lock(mutex_);
  const auto it = connections_.find(peer);
  if (it == connections_.end()) return false;
  if (it->second.ended) return claim_ended();
  it->second.answering = false;
  it->second.since = Clock::now();
  if (!it->second.close_after) return false;
  // cpp-httplib reads on after any answer: what is left of a refused body must not be taken for requests.
  int fd = it->second.fd;
  connections_.erase(it);
  lock.unlock();
  if (fd == -1) {
    for (const posix::AcceptedConnection& a : posix::connections_on_port(port_)) {
      if (a.peer == peer) fd = a.fd;
    }
  }
  if (fd != -1) (void)posix::shut_down_connection(fd, peer);
  return false;
}

void RequestDeadline::close_after_answer(const std::string& peer) {
  std::lock_guard lock(mutex_);
  connections_[peer].close_after = true;
}

void RequestDeadline::run() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    lock.unlock();
    const std::vector<posix::AcceptedConnection> open = posix::connections_on_port(port_);
    const auto now = Clock::now();
    lock.lock();
    for (auto& [peer, c] : connections_) ++c.unseen;
    for (const posix::AcceptedConnection& a : open) {
      auto [it, added] = connections_.try_emplace(a.peer);
      Connection& c = it->second;
      // A new connection (begun() may have come first, from a thread quicker than this look).
      if (c.fd != a.fd) {
        c.fd = a.fd;
        c.since = now;
      }
      c.unseen = 0;
    }
    // Gone: not seen now (one being answered, after a few looks: begun() may precede its first).
    std::erase_if(connections_, [](const auto& entry) { return entry.second.unseen > (entry.second.answering ? 8 : 0); });
    for (auto& [peer, c] : connections_) {
      if (c.answering || c.unseen > 0 || now - c.since < deadline_) continue;
      // Counted before the shutdown: the thread serving it may answer its 400 at once.
      unclaimed_.fetch_add(1, std::memory_order_relaxed);
      if (posix::shut_down_connection(c.fd, peer)) {
        closed_.fetch_add(1, std::memory_order_relaxed);
      } else {
        (void)claim_ended();
      }
      c.since = now;  // once; the thread serving it closes it
      c.ended = true;
    }
    stop_wait_.wait_for(lock, std::chrono::milliseconds(250), [this] { return stopping_; });
  }
}

}  // namespace gpsemu::ui
