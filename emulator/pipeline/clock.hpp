// The epoch clocks (docs/design.md "Timing semantics"), all paced by the one epoch loop (epoch_loop.hpp):
//
// - realtime (default): epoch t leaves at t + latency on the system clock (shifted by whole epochs,
//   or whole seconds with PPS, with --start-time); an epoch more than one period late is skipped.
// - fast: no pacing at all (batch generation; --fast or --clock fast).
// - replay: a scaled clock (K = --speed) on the log's own times that never skips (replayer.hpp).
// - scaled:K: epochs on the same UTC grid, but paced at K times real time from the start: the
//   first epoch t_0 leaves when it would in real time (t_0 + latency, or now with --start-time),
//   epoch t_k (t_k - t_0) / K later. The NMEA times still advance by one epoch period per epoch,
//   so K = 10 at 1 Hz sends 1 s of epochs every 100 ms.
// - lockstep: time advances with the simulator's time stamps. Poses of a udp:/tcp: source carry
//   `t` (seconds), placed at UTC = --start-time (or the first epoch) + t; epoch t_k leaves as soon
//   as a pose with a time at or after t_k has arrived, whatever the wall clock does. The clock
//   waits on the source's file descriptor, never on the wall clock: a simulator slower or faster
//   than real time gets every epoch once, in order. Epochs before the simulator's present at the
//   first pose are skipped (a simulator already running); after that, none are skipped.
//
// The clocks wait through a ClockIo (the loop's outputs and sources, or a fake in tests) and hold
// no other state than where they are on their timeline.
#pragma once

#include <atomic>
#include <cstdint>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/common/log_limit.hpp"
#include "emulator/config/spec/clock_spec.hpp"
#include "emulator/model/time.hpp"
#include "emulator/sources/pose_source.hpp"
#include "transport/posix/wait.hpp"

namespace gpsemu {

/// CLOCK_REALTIME as UTC.
[[nodiscard]] UtcNs system_utc_now();

/// What a clock needs from the world while it waits.
class ClockIo {
 public:
  virtual ~ClockIo() = default;
  /// The wall clock (UTC).
  [[nodiscard]] virtual UtcNs now() = 0;
  /// Waits until the wall clock reaches `deadline`, servicing inputs meanwhile; returns early
  /// only when `stop` becomes true or the wall clock was set (a step: look at now() again).
  virtual void sleep_until(UtcNs deadline, const std::atomic<bool>& stop) = 0;
  /// sleep_until(), returning early also when `woken` returns true after input was serviced (a
  /// u-blox client asked for another solution period). Default: sleep_until().
  virtual void sleep_until_woken(UtcNs deadline, const std::atomic<bool>& stop, const std::function<bool()>& woken) {
    (void)woken;
    sleep_until(deadline, stop);
  }
  /// Waits at most `timeout` for input (pose source, output clients), services what arrived.
  virtual void wait_for_input(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop) = 0;
};

/// The real ClockIo: every wait is a posix::Waiter's (an absolute CLOCK_REALTIME
/// timerfd, polled with the descriptors the lister appends, serviced as input arrives; the timer
/// alone when there is nothing to poll).
class SystemClockIo final : public ClockIo {
 public:
  using FdLister = posix::Waiter::FdLister;
  using ReadyServicer = posix::Waiter::ReadyServicer;
  /// `service` runs once a wake-up on input and services every input. Throws std::runtime_error
  /// when the timerfd cannot be created.
  SystemClockIo(FdLister fds, std::function<void()> service) : waiter_(std::move(fds), std::move(service)) {}
  /// `service` runs for each descriptor that has input (many inputs: only those are serviced).
  SystemClockIo(FdLister fds, ReadyServicer service) : waiter_(std::move(fds), std::move(service)) {}

  UtcNs now() override { return system_utc_now(); }
  void sleep_until(UtcNs deadline, const std::atomic<bool>& stop) override { waiter_.sleep_until(deadline, stop); }
  void sleep_until_woken(UtcNs deadline, const std::atomic<bool>& stop, const std::function<bool()>& woken) override {
    waiter_.sleep_until(deadline, stop, &woken);
  }
  void wait_for_input(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop) override {
    waiter_.wait_for_input(timeout, stop);
  }
  /// Waits that returned because the deadline came or input arrived (a measure of wake-ups: one an
  /// epoch when no input arrives).
  [[nodiscard]] std::uint64_t wakeups() const { return waiter_.wakeups(); }
  /// Waits not made: their deadline had passed already.
  [[nodiscard]] std::uint64_t waits_already_due() const { return waiter_.already_due(); }

 private:
  posix::Waiter waiter_;
};

/// What became of an epoch the clock was asked to wait for.
enum class EpochWait {
  due,      ///< its time has come: sample, format and send it now
  skip,     ///< do not send it (its time is long past, or it precedes the simulator's start)
  stopped,  ///< `stop` became true while waiting
  rescheduled,  ///< a receiver's schedule changed while waiting (EpochLoop only): ask for the next epoch again
};

/// Paces the epochs of one timeline. A clock on the wall clock (realtime, scaled) has a deadline
/// for each epoch, which the epoch loop waits for itself (PPS edges and a fleet's computing go
/// before it); the others (fast, lockstep) only have wait_for().
class EpochClock {
 public:
  virtual ~EpochClock() = default;
  /// Waits until epoch `t` is due. Epochs are asked for in order, each once. For a clock with
  /// deadlines: skip when late(t), else a wait until deadline_of(t).
  [[nodiscard]] virtual EpochWait wait_for(UtcNs t, const std::atomic<bool>& stop);
  /// The wall time epoch `t` leaves at; nullopt for a clock not on the wall clock.
  [[nodiscard]] virtual std::optional<UtcNs> deadline_of(UtcNs /*t*/) const { return std::nullopt; }
  /// The epoch time whose deadline is wall time `wall` (deadline_of()'s inverse); nullopt for a
  /// clock not on the wall clock.
  [[nodiscard]] virtual std::optional<UtcNs> epoch_time_at(UtcNs /*wall*/) const { return std::nullopt; }
  /// True (and says so once in the log) when epoch `t` is so late it is skipped, not sent in a
  /// burst: a receiver never reports the past.
  [[nodiscard]] virtual bool late(UtcNs /*t*/) { return false; }
  /// One line for the start-up banner (empty: none).
  [[nodiscard]] virtual std::string describe() const = 0;
  /// What the clock waits through; nullptr for a clock that never waits (fast).
  [[nodiscard]] virtual ClockIo* io() const { return nullptr; }
  /// The time between epochs now: the finest of the receivers' schedules (a u-blox client may
  /// ask for a faster one than --rate's); how late an epoch may be before it is skipped.
  void set_epoch_period(std::chrono::nanoseconds period) { period_ = period; }
  [[nodiscard]] std::chrono::nanoseconds epoch_period() const { return period_; }

  /// A clock with deadlines, asked before waiting for epoch `t` (epochs in order, each once): when
  /// the wall clock went back since the previous epoch (`now` before that epoch's deadline by more
  /// than half a step unit), every deadline moves back with it, by whole step units (at least the
  /// step), so the epochs go on one period apart from now and their times never go back (a
  /// receiver keeps its own time). Returns how far the deadlines moved (0: the clock did not go back).
  [[nodiscard]] std::chrono::nanoseconds follow_step_back(UtcNs t, UtcNs now);
  /// The epoch follow_step_back() was asked for last was given up before its deadline (a client
  /// changed the solution rate): the next epoch is compared with the one before it, not with this
  /// one, whose later deadline would look like a wall clock that went back.
  void abandon_current() { current_ = previous_; }
  /// How far the deadlines moved back in all (the epochs' times are that far ahead of the wall clock).
  [[nodiscard]] std::chrono::nanoseconds moved_back() const { return moved_back_; }

 protected:
  EpochClock() = default;
  explicit EpochClock(std::chrono::nanoseconds epoch_period) : period_(epoch_period) {}
  /// Moves every deadline `by` earlier (the wall clock went back).
  virtual void move_deadlines_back(std::chrono::nanoseconds /*by*/) {}
  std::chrono::nanoseconds period_{0};
  LogLimit skip_log_{5};  ///< "epoch ... skipped" lines: at most 5 a second
  /// What follow_step_back() moves the deadlines by a multiple of: the epoch period (whole epochs
  /// keep each epoch's phase on the wall clock), a second with PPS; 0: exactly the step.
  std::chrono::nanoseconds step_unit_{0};

 private:
  std::optional<UtcNs> current_;   ///< the epoch follow_step_back() was asked for last
  std::optional<UtcNs> previous_;  ///< the one before it
  std::chrono::nanoseconds moved_back_{0};
};

/// fast: every epoch is due at once.
class FastClock final : public EpochClock {
 public:
  [[nodiscard]] EpochWait wait_for(UtcNs, const std::atomic<bool>& stop) override {
    return stop.load() ? EpochWait::stopped : EpochWait::due;
  }
  [[nodiscard]] std::string describe() const override { return {}; }
};

/// realtime: epoch t leaves at t - epoch_minus_wall + latency on the system clock; an epoch more
/// than one epoch period late is skipped.
class RealtimeClock final : public EpochClock {
 public:
  /// `step_unit`: what a step back of the wall clock moves the deadlines by a multiple of (the
  /// epoch period; a second with PPS, so the epoch stamped S still follows pulse S); 0: the period.
  RealtimeClock(ClockIo& io, std::chrono::nanoseconds epoch_minus_wall, std::chrono::nanoseconds latency,
                std::chrono::nanoseconds epoch_period, std::chrono::nanoseconds step_unit = {})
      : EpochClock(epoch_period), io_(io), shift_(epoch_minus_wall), latency_(latency) {
    step_unit_ = step_unit > std::chrono::nanoseconds::zero() ? step_unit : epoch_period;
  }
  [[nodiscard]] std::optional<UtcNs> deadline_of(UtcNs t) const override { return t - shift_ + latency_; }
  [[nodiscard]] std::optional<UtcNs> epoch_time_at(UtcNs wall) const override { return wall + shift_ - latency_; }
  [[nodiscard]] bool late(UtcNs t) override;
  [[nodiscard]] std::string describe() const override { return {}; }
  [[nodiscard]] ClockIo* io() const override { return &io_; }

 protected:
  void move_deadlines_back(std::chrono::nanoseconds by) override { shift_ += by; }

 private:
  ClockIo& io_;
  std::chrono::nanoseconds shift_, latency_;
};

/// scaled:K. `first_epoch` leaves at wall time `first_wall` (its real-time deadline: latency
/// included); epoch t at first_wall + (t - first_epoch) / K. An epoch more than one epoch
/// period (wall) late is skipped, like the real-time loop does, unless `skip_late` is false
/// (replay: every recorded epoch is sent, the delay is measured).
class ScaledClock final : public EpochClock {
 public:
  /// Throws std::invalid_argument for a scale outside (0, 1000].
  ScaledClock(ClockIo& io, double scale, UtcNs first_epoch, UtcNs first_wall, std::chrono::nanoseconds epoch_period,
              bool skip_late = true);
  [[nodiscard]] std::optional<UtcNs> deadline_of(UtcNs t) const override;
  [[nodiscard]] std::optional<UtcNs> epoch_time_at(UtcNs wall) const override;
  [[nodiscard]] bool late(UtcNs t) override;
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] ClockIo* io() const override { return &io_; }

 protected:
  void move_deadlines_back(std::chrono::nanoseconds by) override { first_wall_ -= by; }

 private:
  ClockIo& io_;
  double scale_;
  UtcNs first_epoch_;
  UtcNs first_wall_;
  bool skip_late_;
};

/// lockstep: epoch t is due once `source.sim_time()` is at or after t.
class LockstepClock final : public EpochClock {
 public:
  /// `poll_interval`: longest wait for input before the stop flag is looked at again.
  LockstepClock(ClockIo& io, const sources::PoseSource& source, std::chrono::nanoseconds epoch_period,
                std::chrono::nanoseconds poll_interval = std::chrono::milliseconds(100));
  [[nodiscard]] EpochWait wait_for(UtcNs t, const std::atomic<bool>& stop) override;
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] ClockIo* io() const override { return &io_; }

 private:
  ClockIo& io_;
  const sources::PoseSource& source_;
  std::chrono::nanoseconds poll_interval_;
  bool started_ = false;  ///< an epoch has been due: from now on none is skipped
};

/// The clock `spec` names. `first_wall` is the first epoch's real-time deadline; `epoch_minus_wall`
/// and `latency` place the real-time deadlines.
[[nodiscard]] std::unique_ptr<EpochClock> make_epoch_clock(const ClockSpec& spec, ClockIo& io,
                                                           const sources::PoseSource& source, UtcNs first_epoch,
                                                           UtcNs first_wall, std::chrono::nanoseconds epoch_period,
                                                           std::chrono::nanoseconds epoch_minus_wall,
                                                           std::chrono::nanoseconds latency,
                                                           std::chrono::nanoseconds step_unit = {});

}  // namespace gpsemu
