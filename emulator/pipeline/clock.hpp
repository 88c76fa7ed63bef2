// The epoch clocks besides the runner's own real-time pacing (docs/design.md "Timing semantics"):
//
// - realtime (default): epoch t leaves at t + latency on the system clock (the runner's own loop).
// - fast: no pacing at all (batch generation; --fast or --clock fast).
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
// The clocks wait through a ClockIo (the runner's outputs and source, or a fake in tests) and hold
// no other state than where they are on their timeline.
#pragma once

#include <poll.h>

#include <atomic>
#include <cstdint>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/sources/pose_source.hpp"
#include "emulator/model/time.hpp"

namespace gpsemu {

enum class ClockKind { realtime, scaled, fast, lockstep };

/// What --clock names.
struct ClockSpec {
  ClockKind kind = ClockKind::realtime;
  double scale = 1.0;  ///< scaled: wall-clock speed-up factor K (0.01..1000); 1 otherwise

  friend bool operator==(const ClockSpec&, const ClockSpec&) = default;
};

/// Parses "realtime", "fast", "lockstep" or "scaled:K" (K from 0.01 to 1000, e.g. scaled:2 or
/// scaled:0.5). Throws std::invalid_argument naming the text and the accepted forms.
[[nodiscard]] ClockSpec parse_clock_spec(std::string_view text);
/// The spec written back: "scaled:2", "lockstep", ...
[[nodiscard]] std::string to_string(const ClockSpec& spec);

/// CLOCK_REALTIME as UTC.
[[nodiscard]] UtcNs system_utc_now();

/// What a clock needs from the world while it waits.
class ClockIo {
 public:
  virtual ~ClockIo() = default;
  /// The wall clock (UTC).
  [[nodiscard]] virtual UtcNs now() = 0;
  /// Waits until the wall clock reaches `deadline`, servicing inputs meanwhile; returns early
  /// only when `stop` becomes true.
  virtual void sleep_until(UtcNs deadline, const std::atomic<bool>& stop) = 0;
  /// Waits at most `timeout` for input (pose source, output clients), services what arrived.
  virtual void wait_for_input(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop) = 0;
};

/// The real ClockIo. A wait is one poll() over an absolute CLOCK_REALTIME timerfd (armed at the
/// deadline) and the descriptors the lister appends: servicing inputs as they arrive, and exactly
/// one wake-up at the deadline when nothing else happens (no early wake-up and final sleep, no
/// timer slack: the timerfd's hrtimer fires at the deadline). The wall clock being stepped moves the
/// wake-up with it (absolute timer). Lists are reused: no allocation per wait.
class SystemClockIo final : public ClockIo {
 public:
  /// Appends the descriptors to watch for input (readable) to the vector it is given.
  using FdLister = std::function<void(std::vector<int>&)>;
  /// Services the input of the k-th descriptor the lister appended (readable or hung up).
  using ReadyServicer = std::function<void(std::size_t k)>;
  /// `service` runs once a wake-up on input and services every input. Throws std::runtime_error
  /// when the timerfd cannot be created.
  SystemClockIo(FdLister fds, std::function<void()> service);
  /// `service` runs for each descriptor that has input (many inputs: only those are serviced).
  SystemClockIo(FdLister fds, ReadyServicer service);
  ~SystemClockIo() override;
  SystemClockIo(const SystemClockIo&) = delete;
  SystemClockIo& operator=(const SystemClockIo&) = delete;

  UtcNs now() override { return system_utc_now(); }
  void sleep_until(UtcNs deadline, const std::atomic<bool>& stop) override;
  void wait_for_input(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop) override;
  /// poll() calls that returned because the deadline's timer fired or input arrived (a measure of
  /// wake-ups: one an epoch when no input arrives).
  [[nodiscard]] std::uint64_t wakeups() const { return wakeups_; }

 private:
  /// Rebuilds the poll list: [timer] + the lister's descriptors (servicing may close or open one).
  void build_poll_list(bool with_timer);
  std::function<void(std::vector<int>&)> fds_;
  std::function<void()> service_;       ///< or:
  ReadyServicer service_ready_;
  /// Runs the servicer for what poll_list_ reported.
  void service_polled();
  int timer_fd_ = -1;
  std::vector<int> fd_list_;       ///< reused
  std::vector<pollfd> poll_list_;  ///< reused
  std::uint64_t wakeups_ = 0;
};

/// What became of an epoch the clock was asked to wait for.
enum class EpochWait {
  due,      ///< its time has come: sample, format and send it now
  skip,     ///< do not send it (its time is long past, or it precedes the simulator's start)
  stopped,  ///< `stop` became true while waiting
};

class EpochClock {
 public:
  virtual ~EpochClock() = default;
  /// Waits until epoch `t` is due. Epochs are asked for in order, each once.
  [[nodiscard]] virtual EpochWait wait_for(UtcNs t, const std::atomic<bool>& stop) = 0;
  /// One line for the start-up banner.
  [[nodiscard]] virtual std::string describe() const = 0;
};

/// scaled:K. `first_epoch` leaves at wall time `first_wall` (its real-time deadline: latency
/// included); epoch t at first_wall + (t - first_epoch) / K. An epoch more than one epoch
/// period (wall) late is skipped, like the real-time loop does.
class ScaledClock final : public EpochClock {
 public:
  /// Throws std::invalid_argument for a scale outside (0, 1000].
  ScaledClock(ClockIo& io, double scale, UtcNs first_epoch, UtcNs first_wall, std::chrono::nanoseconds epoch_period);
  [[nodiscard]] EpochWait wait_for(UtcNs t, const std::atomic<bool>& stop) override;
  [[nodiscard]] std::string describe() const override;
  /// When epoch `t` leaves (wall clock, UTC).
  [[nodiscard]] UtcNs deadline_of(UtcNs t) const;

 private:
  ClockIo& io_;
  double scale_;
  UtcNs first_epoch_;
  UtcNs first_wall_;
  std::chrono::nanoseconds period_;
};

/// lockstep: epoch t is due once `source.sim_time()` is at or after t.
class LockstepClock final : public EpochClock {
 public:
  /// `poll_interval`: longest wait for input before the stop flag is looked at again.
  LockstepClock(ClockIo& io, const sources::PoseSource& source, std::chrono::nanoseconds epoch_period,
                std::chrono::nanoseconds poll_interval = std::chrono::milliseconds(100));
  [[nodiscard]] EpochWait wait_for(UtcNs t, const std::atomic<bool>& stop) override;
  [[nodiscard]] std::string describe() const override;

 private:
  ClockIo& io_;
  const sources::PoseSource& source_;
  std::chrono::nanoseconds period_;
  std::chrono::nanoseconds poll_interval_;
  bool started_ = false;  ///< an epoch has been due: from now on none is skipped
};

/// The clock `spec` names for the runner, or nullptr for realtime and fast (the runner's own
/// loop). `first_wall` is the first epoch's real-time deadline.
[[nodiscard]] std::unique_ptr<EpochClock> make_epoch_clock(const ClockSpec& spec, ClockIo& io,
                                                           const sources::PoseSource& source, UtcNs first_epoch,
                                                           UtcNs first_wall, std::chrono::nanoseconds epoch_period);

}  // namespace gpsemu
