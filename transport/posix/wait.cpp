#include "transport/posix/wait.hpp"

#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <stdexcept>
#include <string>

#include "transport/posix/errors.hpp"

namespace gpsemu::posix {

Waiter::Waiter() : Waiter(FdLister{}, std::function<void()>{}) {}

Waiter::Waiter(FdLister fds, ReadyServicer service) : Waiter(std::move(fds), std::function<void()>{}) {
  service_ready_ = std::move(service);
}

Waiter::Waiter(FdLister fds, std::function<void()> service) : fds_(std::move(fds)), service_(std::move(service)) {
  timer_fd_ = ::timerfd_create(CLOCK_REALTIME, TFD_CLOEXEC);
  if (timer_fd_ < 0) {
    throw std::runtime_error(std::string("cannot create a CLOCK_REALTIME timerfd: ") + errno_text(errno));
  }
}

Waiter::~Waiter() {
  if (timer_fd_ >= 0) ::close(timer_fd_);
}

void Waiter::build_poll_list(bool with_timer) {
  fd_list_.clear();
  if (fds_) fds_(fd_list_);
  poll_list_.clear();
  if (with_timer) poll_list_.push_back({timer_fd_, POLLIN, 0});
  for (const int fd : fd_list_) poll_list_.push_back({fd, POLLIN, 0});
}

void Waiter::service_polled() {
  if (!service_ready_) {
    if (service_) service_();
    return;
  }
  const std::size_t first = poll_list_.size() - fd_list_.size();  // after the timer, if listed
  for (std::size_t k = first; k < poll_list_.size(); ++k) {
    if (poll_list_[k].revents != 0) service_ready_(k - first);
  }
}

bool Waiter::read_timer(const std::atomic<bool>& stop) {
  std::uint64_t expirations = 0;
  while (!stop.load()) {
    if (::read(timer_fd_, &expirations, sizeof expirations) > 0) return true;
    if (errno != EINTR) return false;
  }
  return false;
}

void Waiter::sleep_until(WallTime deadline, const std::atomic<bool>& stop, const std::function<bool()>* woken) {
  if (stop.load()) return;
  if (wall_clock_now() >= deadline) {
    ++already_due_;  // no wait, no wake-up
    return;
  }
  const std::int64_t ns = deadline.time_since_epoch().count();
  itimerspec when{};
  when.it_value = {static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
  // Arming resets the timer's expiry count: a fired, unread timer of an earlier wait is forgotten.
  // A wall clock set meanwhile (a step back or ahead) ends the wait early (the timer reads
  // ECANCELED, poll() sees it readable): the caller looks at the clock again.
  if (::timerfd_settime(timer_fd_, TFD_TIMER_ABSTIME | TFD_TIMER_CANCEL_ON_SET, &when, nullptr) != 0) {
    // Cannot happen with a valid descriptor and time; sleep without servicing rather than spin.
    while (!stop.load() && clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME, &when.it_value, nullptr) == EINTR) {
    }
    return;
  }
  while (!stop.load()) {
    // Rebuilt each time: servicing may close a descriptor (a client went away) or open one.
    build_poll_list(true);
    if (poll_list_.size() == 1) {
      // Nothing to poll: the timer alone, one system call.
      if (read_timer(stop)) {
        ++wakeups_;
        return;
      }
      break;
    }
    const int ready = ::poll(poll_list_.data(), poll_list_.size(), -1);
    if (ready < 0) continue;  // EINTR: a signal; the stop flag says whether to go on
    ++wakeups_;
    if (poll_list_.front().revents & POLLIN) return;
    // Input at or after the deadline waits for the next wait: the deadline's work goes first
    // (and another thread may be writing to the outputs from the deadline on).
    if (wall_clock_now() >= deadline) break;
    service_polled();
    if (woken && (*woken)()) break;  // what was serviced changes what the wait is for
    const bool input = std::any_of(poll_list_.begin() + 1, poll_list_.end(),
                                   [](const pollfd& p) { return (p.revents & POLLIN) != 0; });
    if (!input) {
      // Only hang-up/error conditions, which poll() keeps reporting until the owner closes the
      // descriptor: wait for the timer alone for 1 ms instead of spinning on them.
      pollfd timer{timer_fd_, POLLIN, 0};
      if (::poll(&timer, 1, 1) > 0) return;
    }
  }
  // Stopped or past the deadline without the timer's wake-up: disarm, so a later wait does not
  // see this deadline's expiry.
  const itimerspec off{};
  ::timerfd_settime(timer_fd_, 0, &off, nullptr);
}

void Waiter::wait_for_input(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop) {
  if (stop.load()) return;
  build_poll_list(false);
  const auto ms = std::chrono::ceil<std::chrono::milliseconds>(timeout).count();
  const int ready = ::poll(poll_list_.data(), poll_list_.size(), static_cast<int>(std::max<std::int64_t>(ms, 0)));
  if (ready > 0) {
    ++wakeups_;
    service_polled();
  }
}

}  // namespace gpsemu::posix
