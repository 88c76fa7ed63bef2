// The one way gpsemu waits for a wall-clock instant (every epoch, PPS edge and fleet write):
// an absolute CLOCK_REALTIME timerfd, so the wake-up is at the deadline (an hrtimer without
// timer slack, no early wake-up and final sleep) and a stepped wall clock moves it along. While
// waiting, the descriptors a lister names (pose sockets, output clients) are polled and serviced
// as input arrives. With nothing to poll the wait is a blocking read of the timer alone.
// Per wait: timerfd_settime + poll (or read) = two system calls and one wake-up when no input
// arrives (re-arming resets the timer's count: no read is needed to clear it).
#pragma once

#include <poll.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <vector>

#include "transport/posix/wall_clock.hpp"

namespace gpsemu::posix {

class Waiter {
 public:
  /// Appends the descriptors to watch for input (readable) to the vector it is given.
  using FdLister = std::function<void(std::vector<int>&)>;
  /// Services the input of the k-th descriptor the lister appended (readable or hung up).
  using ReadyServicer = std::function<void(std::size_t k)>;
  /// Nothing to poll: waits are on the timer alone.
  Waiter();
  /// `service` runs once a wake-up on input and services every input.
  Waiter(FdLister fds, std::function<void()> service);
  /// `service` runs for each descriptor that has input (many inputs: only those are serviced).
  Waiter(FdLister fds, ReadyServicer service);
  ~Waiter();
  Waiter(const Waiter&) = delete;
  Waiter& operator=(const Waiter&) = delete;

  /// Waits until the wall clock reaches `deadline`, servicing inputs meanwhile; returns early only
  /// when `stop` becomes true (a signal interrupts the wait), when the wall clock was set (a step:
  /// the caller looks at the clock again), or when `woken` (if given) returns true after input was
  /// serviced. A past deadline returns at once.
  void sleep_until(WallTime deadline, const std::atomic<bool>& stop, const std::function<bool()>* woken = nullptr);
  /// Waits at most `timeout` for input and services what arrived.
  void wait_for_input(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop);
  /// Waits that returned because the deadline came or input arrived (one an epoch when no input
  /// arrives).
  [[nodiscard]] std::uint64_t wakeups() const { return wakeups_; }
  /// Waits not made: the deadline had already passed when the wait was asked for (a slow start-up,
  /// a busy machine), so no wake-up either.
  [[nodiscard]] std::uint64_t already_due() const { return already_due_; }

 private:
  /// Rebuilds the poll list: [timer] + the lister's descriptors (servicing may close or open one).
  void build_poll_list(bool with_timer);
  /// Runs the servicer for what poll_list_ reported.
  void service_polled();
  /// Blocks on the armed timer alone (nothing to poll). True when it fired.
  bool read_timer(const std::atomic<bool>& stop);
  FdLister fds_;
  std::function<void()> service_;  ///< or:
  ReadyServicer service_ready_;
  int timer_fd_ = -1;  ///< blocking: read() waits for the expiry
  std::vector<int> fd_list_;       ///< reused: no allocation per wait
  std::vector<pollfd> poll_list_;  ///< reused
  std::uint64_t wakeups_ = 0;
  std::uint64_t already_due_ = 0;
};

}  // namespace gpsemu::posix
