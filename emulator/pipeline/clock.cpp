#include "emulator/pipeline/clock.hpp"

#include <poll.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "transport/posix/wall_clock.hpp"

namespace gpsemu {
namespace {

double seconds(std::chrono::nanoseconds d) { return std::chrono::duration<double>(d).count(); }

}  // namespace

ClockSpec parse_clock_spec(std::string_view text) {
  if (text == "realtime") return {};
  if (text == "fast") return {ClockKind::fast, 1.0};
  if (text == "lockstep") return {ClockKind::lockstep, 1.0};
  if (text.rfind("scaled:", 0) == 0) {
    const std::string_view k = text.substr(7);
    double scale = 0.0;
    const auto [ptr, ec] = std::from_chars(k.data(), k.data() + k.size(), scale);
    if (k.empty() || ec != std::errc{} || ptr != k.data() + k.size() || !std::isfinite(scale)) {
      throw std::invalid_argument(fmt::format("clock '{}': K in scaled:K must be a number, e.g. scaled:2", text));
    }
    if (scale < 0.01 || scale > 1000.0) {
      throw std::invalid_argument(fmt::format("clock '{}': K in scaled:K must be from 0.01 to 1000", text));
    }
    return {ClockKind::scaled, scale};
  }
  throw std::invalid_argument(
      fmt::format("unknown clock '{}' (accepted: realtime, scaled:K, fast, lockstep)", text));
}

std::string to_string(const ClockSpec& spec) {
  switch (spec.kind) {
    case ClockKind::realtime: return "realtime";
    case ClockKind::fast: return "fast";
    case ClockKind::lockstep: return "lockstep";
    case ClockKind::scaled: return fmt::format("scaled:{}", spec.scale);
  }
  return "?";
}

UtcNs system_utc_now() { return posix::wall_clock_now(); }

// ---- SystemClockIo ----------------------------------------------------------------------------

SystemClockIo::SystemClockIo(FdLister fds, ReadyServicer service)
    : SystemClockIo(std::move(fds), std::function<void()>{}) {
  service_ready_ = std::move(service);
}

SystemClockIo::SystemClockIo(FdLister fds, std::function<void()> service)
    : fds_(std::move(fds)), service_(std::move(service)) {
  timer_fd_ = ::timerfd_create(CLOCK_REALTIME, TFD_CLOEXEC | TFD_NONBLOCK);
  if (timer_fd_ < 0) {
    throw std::runtime_error(fmt::format("cannot create a CLOCK_REALTIME timerfd: {}", std::strerror(errno)));
  }
}

SystemClockIo::~SystemClockIo() {
  if (timer_fd_ >= 0) ::close(timer_fd_);
}

void SystemClockIo::build_poll_list(bool with_timer) {
  fd_list_.clear();
  fds_(fd_list_);
  poll_list_.clear();
  if (with_timer) poll_list_.push_back({timer_fd_, POLLIN, 0});
  for (const int fd : fd_list_) poll_list_.push_back({fd, POLLIN, 0});
}

void SystemClockIo::service_polled() {
  if (!service_ready_) {
    if (service_) service_();
    return;
  }
  const std::size_t first = poll_list_.size() - fd_list_.size();  // after the timer, if listed
  for (std::size_t k = first; k < poll_list_.size(); ++k) {
    if (poll_list_[k].revents != 0) service_ready_(k - first);
  }
}

void SystemClockIo::sleep_until(UtcNs deadline, const std::atomic<bool>& stop) {
  if (stop.load() || system_utc_now() >= deadline) return;
  const std::int64_t ns = deadline.time_since_epoch().count();
  itimerspec when{};
  when.it_value = {static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
  if (::timerfd_settime(timer_fd_, TFD_TIMER_ABSTIME, &when, nullptr) != 0) {
    // Cannot happen with a valid descriptor and time; sleep without servicing rather than spin.
    while (!stop.load() && clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME, &when.it_value, nullptr) == EINTR) {
    }
    return;
  }
  while (!stop.load()) {
    // Rebuilt each time: servicing may close a descriptor (a client went away) or open one.
    build_poll_list(true);
    const int ready = ::poll(poll_list_.data(), poll_list_.size(), -1);
    if (ready < 0) continue;  // EINTR: a signal; the stop flag says whether to go on
    ++wakeups_;
    if (poll_list_.front().revents & POLLIN) {
      std::uint64_t expirations = 0;
      (void)!::read(timer_fd_, &expirations, sizeof expirations);
      return;
    }
    // Input at or after the deadline waits for the next wait: the deadline's work goes first
    // (and another thread may be writing to the outputs from the deadline on).
    if (system_utc_now() >= deadline) break;
    service_polled();
    bool input = false;
    for (std::size_t k = 1; k < poll_list_.size(); ++k) input = input || (poll_list_[k].revents & POLLIN);
    if (!input) {
      // Only hang-up/error conditions, which poll() keeps reporting until the owner closes the
      // descriptor: wait for the timer alone for 1 ms instead of spinning on them.
      pollfd timer{timer_fd_, POLLIN, 0};
      if (::poll(&timer, 1, 1) > 0) {
        std::uint64_t expirations = 0;
        (void)!::read(timer_fd_, &expirations, sizeof expirations);
        return;
      }
    }
  }
  // Stopped or past the deadline without the timer's wake-up: disarm, so a later wait does not
  // see this deadline's expiry.
  const itimerspec off{};
  ::timerfd_settime(timer_fd_, 0, &off, nullptr);
}

void SystemClockIo::wait_for_input(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop) {
  if (stop.load()) return;
  build_poll_list(false);
  const auto ms = std::chrono::ceil<std::chrono::milliseconds>(timeout).count();
  const int ready = ::poll(poll_list_.data(), poll_list_.size(), static_cast<int>(std::max<std::int64_t>(ms, 0)));
  if (ready > 0) {
    ++wakeups_;
    service_polled();
  }
}

// ---- ScaledClock ------------------------------------------------------------------------------

ScaledClock::ScaledClock(ClockIo& io, double scale, UtcNs first_epoch, UtcNs first_wall,
                         std::chrono::nanoseconds epoch_period)
    : io_(io), scale_(scale), first_epoch_(first_epoch), first_wall_(first_wall), period_(epoch_period) {
  if (!(scale > 0.0) || scale > 1000.0) {
    throw std::invalid_argument(fmt::format("scaled clock: K must be > 0 and <= 1000, got {}", scale));
  }
}

UtcNs ScaledClock::deadline_of(UtcNs t) const {
  const auto since = static_cast<double>((t - first_epoch_).count());
  return first_wall_ + std::chrono::nanoseconds{std::llround(since / scale_)};
}

EpochWait ScaledClock::wait_for(UtcNs t, const std::atomic<bool>& stop) {
  const UtcNs deadline = deadline_of(t);
  // Like the real-time loop: an epoch whose (scaled) time has long passed is not sent in a burst.
  const auto late = io_.now() - deadline;
  const auto wall_period = std::chrono::nanoseconds{std::llround(static_cast<double>(period_.count()) / scale_)};
  if (late > std::max<std::chrono::nanoseconds>(wall_period, std::chrono::milliseconds(20))) {
    spdlog::warn("epoch {} skipped: {:.0f} ms late on the scaled clock", format_iso8601_utc(t), seconds(late) * 1e3);
    return EpochWait::skip;
  }
  io_.sleep_until(deadline, stop);
  return stop.load() ? EpochWait::stopped : EpochWait::due;
}

std::string ScaledClock::describe() const {
  return fmt::format("scaled clock: epochs paced at {}x real time (NMEA times advance {} s an epoch)", scale_,
                     seconds(period_));
}

// ---- LockstepClock ----------------------------------------------------------------------------

LockstepClock::LockstepClock(ClockIo& io, const sources::PoseSource& source, std::chrono::nanoseconds epoch_period,
                             std::chrono::nanoseconds poll_interval)
    : io_(io), source_(source), period_(epoch_period), poll_interval_(poll_interval) {}

EpochWait LockstepClock::wait_for(UtcNs t, const std::atomic<bool>& stop) {
  while (!stop.load()) {
    if (const auto sim = source_.sim_time()) {
      // At start, the simulator may already be far along: begin with the latest epoch it has
      // reached rather than sending everything since the first epoch at once.
      if (!started_ && t + period_ <= *sim) return EpochWait::skip;
      if (*sim >= t) {
        started_ = true;
        return EpochWait::due;
      }
    }
    io_.wait_for_input(poll_interval_, stop);
  }
  return EpochWait::stopped;
}

std::string LockstepClock::describe() const {
  return "lockstep clock: an epoch leaves when the simulator's time (pose 't') reaches it";
}

std::unique_ptr<EpochClock> make_epoch_clock(const ClockSpec& spec, ClockIo& io, const sources::PoseSource& source,
                                             UtcNs first_epoch, UtcNs first_wall,
                                             std::chrono::nanoseconds epoch_period) {
  switch (spec.kind) {
    case ClockKind::scaled: return std::make_unique<ScaledClock>(io, spec.scale, first_epoch, first_wall, epoch_period);
    case ClockKind::lockstep: return std::make_unique<LockstepClock>(io, source, epoch_period);
    case ClockKind::realtime:
    case ClockKind::fast: return nullptr;
  }
  return nullptr;
}

}  // namespace gpsemu
