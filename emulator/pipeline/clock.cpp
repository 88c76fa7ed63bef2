#include "emulator/pipeline/clock.hpp"

#include <time.h>

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "transport/posix/wall_clock.hpp"

namespace gpsemu {
namespace {

double seconds(std::chrono::nanoseconds d) { return std::chrono::duration<double>(d).count(); }

}  // namespace

UtcNs system_utc_now() { return posix::wall_clock_now(); }

// ---- EpochClock, RealtimeClock -------------------------------------------------------------

EpochWait EpochClock::wait_for(UtcNs t, const std::atomic<bool>& stop) {
  const auto deadline = deadline_of(t);
  if (!deadline || !io()) return stop.load() ? EpochWait::stopped : EpochWait::due;
  if (late(t)) return EpochWait::skip;
  io()->sleep_until(*deadline, stop);
  return stop.load() ? EpochWait::stopped : EpochWait::due;
}

std::chrono::nanoseconds EpochClock::follow_step_back(UtcNs t, UtcNs now) {
  if (t != current_) previous_ = std::exchange(current_, t);  // asked again for the same epoch: the same one before
  const std::optional<UtcNs> previous = previous_;
  if (!previous) return std::chrono::nanoseconds::zero();
  const std::optional<UtcNs> previous_deadline = deadline_of(*previous);
  if (!previous_deadline) return std::chrono::nanoseconds::zero();
  // The previous epoch was sent at or after its deadline, or skipped for being late: the wall
  // clock can be before that deadline only if it went back.
  const auto back = *previous_deadline - now;
  const auto unit = step_unit_;
  if (unit > std::chrono::nanoseconds::zero() ? back <= unit / 2 : back <= std::chrono::milliseconds(1)) {
    return std::chrono::nanoseconds::zero();
  }
  const auto by = unit > std::chrono::nanoseconds::zero() ? unit * ((back.count() + unit.count() - 1) / unit.count()) : back;
  move_deadlines_back(by);
  moved_back_ += by;
  return by;
}

bool RealtimeClock::late(UtcNs t) {
  const UtcNs deadline = t - shift_ + latency_;
  const auto behind = io_.now() - deadline;
  if (behind <= period_) return false;
  log_limited(skip_log_, spdlog::level::warn, "epoch {} skipped: {} ms late", format_iso8601_utc(t),
               std::chrono::duration_cast<std::chrono::milliseconds>(behind).count());
  return true;
}

// ---- ScaledClock ------------------------------------------------------------------------------

ScaledClock::ScaledClock(ClockIo& io, double scale, UtcNs first_epoch, UtcNs first_wall,
                         std::chrono::nanoseconds epoch_period, bool skip_late)
    : EpochClock(epoch_period),
      io_(io),
      scale_(scale),
      first_epoch_(first_epoch),
      first_wall_(first_wall),
      skip_late_(skip_late) {
  if (!(scale > 0.0) || scale > 1000.0) {
    throw std::invalid_argument(fmt::format("scaled clock: K must be > 0 and <= 1000, got {}", scale));
  }
}

std::optional<UtcNs> ScaledClock::deadline_of(UtcNs t) const {
  const auto since = static_cast<double>((t - first_epoch_).count());
  return first_wall_ + std::chrono::nanoseconds{std::llround(since / scale_)};
}

std::optional<UtcNs> ScaledClock::epoch_time_at(UtcNs wall) const {
  const auto since = static_cast<double>((wall - first_wall_).count());
  return first_epoch_ + std::chrono::nanoseconds{std::llround(since * scale_)};
}

bool ScaledClock::late(UtcNs t) {
  if (!skip_late_) return false;
  // Like the real-time clock: an epoch whose (scaled) time has long passed is not sent in a burst.
  const auto behind = io_.now() - *deadline_of(t);
  const auto wall_period = std::chrono::nanoseconds{std::llround(static_cast<double>(period_.count()) / scale_)};
  if (behind <= std::max<std::chrono::nanoseconds>(wall_period, std::chrono::milliseconds(20))) return false;
  log_limited(skip_log_, spdlog::level::warn, "epoch {} skipped: {:.0f} ms late on the scaled clock",
                         format_iso8601_utc(t), seconds(behind) * 1e3);
  return true;
}

std::string ScaledClock::describe() const {
  return fmt::format("scaled clock: epochs paced at {}x real time (NMEA times advance {} s an epoch)", scale_,
                     seconds(period_));
}

// ---- LockstepClock ----------------------------------------------------------------------------

LockstepClock::LockstepClock(ClockIo& io, const sources::PoseSource& source, std::chrono::nanoseconds epoch_period,
                             std::chrono::nanoseconds poll_interval)
    : EpochClock(epoch_period), io_(io), source_(source), poll_interval_(poll_interval) {}

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
                                             UtcNs first_epoch, UtcNs first_wall, std::chrono::nanoseconds epoch_period,
                                             std::chrono::nanoseconds epoch_minus_wall,
                                             std::chrono::nanoseconds latency, std::chrono::nanoseconds step_unit) {
  switch (spec.kind) {
    case ClockKind::scaled: return std::make_unique<ScaledClock>(io, spec.scale, first_epoch, first_wall, epoch_period);
    case ClockKind::lockstep: return std::make_unique<LockstepClock>(io, source, epoch_period);
    case ClockKind::realtime: return std::make_unique<RealtimeClock>(io, epoch_minus_wall, latency, epoch_period, step_unit);
    case ClockKind::fast: return std::make_unique<FastClock>();
  }
  return nullptr;
}

}  // namespace gpsemu
