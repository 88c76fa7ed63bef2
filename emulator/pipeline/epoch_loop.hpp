// The one epoch loop, for the emulator (one receiver or a fleet) and replay alike: a producer
// makes each receiver's bytes for an epoch (receiver channels, or recorded epochs), one clock
// paces the epochs (realtime, scaled:K, lockstep, fast: clock.hpp), and one sink sends them.
//
// For a clock on the wall clock each epoch has a deadline (absolute: nothing drifts): the PPS
// edges due before it are driven first (pps_timeline.hpp), an epoch too late is skipped, the loop
// waits for the deadline (one wake-up when no input arrives) and the bytes go out. A fleet in real
// time computes every receiver's epoch ahead of the deadline (by a lead that follows the measured
// cost, never before the epoch's own time), so at the deadline only the writes are left; from 8
// receivers on, a second thread (helper_writer.hpp) writes half of them from the same instant, in
// an order that rotates every epoch so no receiver is always last.
#pragma once

#include <atomic>
#include <functional>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "emulator/model/time.hpp"
#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/helper_writer.hpp"
#include "emulator/pipeline/pps_timeline.hpp"
#include "emulator/pipeline/sink.hpp"

namespace gpsemu {

/// What makes the epochs: receiver i's bytes go to the sink's receiver i.
class EpochProducer {
 public:
  virtual ~EpochProducer() = default;
  /// Sets `t` to the next epoch's time on the clock's timeline; false when there is none left.
  /// (A bool and an out-parameter, not an optional: this runs a million times a second.)
  [[nodiscard]] virtual bool next_epoch(UtcNs& t) = 0;
  /// False when no receiver has an epoch at the time next_epoch() returned: the loop waits for it
  /// (the ports stay open, serviced) and sends and counts nothing.
  [[nodiscard]] virtual bool any_due() const { return true; }
  /// False for a receiver with nothing more to send (its source ended).
  [[nodiscard]] virtual bool active(std::size_t /*i*/) const { return true; }
  /// Receiver i's bytes for epoch `t` (the epoch next_epoch() returned); valid until the next call
  /// for the same receiver.
  [[nodiscard]] virtual std::string_view produce(std::size_t i, UtcNs t) = 0;
  /// Its inputs' descriptors (pose sockets), and their servicing when nothing is polled.
  virtual void list_inputs(std::vector<int>& /*fds*/, std::vector<std::size_t>& /*owners*/) const {}
  virtual void service_input(std::size_t /*owner*/) {}
  virtual void service_inputs() {}
  /// Whether a receiver's schedule changes before the epoch being waited for (a u-blox client
  /// asked for another solution period): the loop stops waiting, calls reschedule() and asks
  /// next_epoch() again.
  [[nodiscard]] virtual bool reschedule_wanted() const { return false; }
  /// Applies the schedule changes at epoch time `now`; the epoch next_epoch() returned last is
  /// not sent (it comes again from next_epoch() for the receivers it was due for).
  virtual void reschedule(UtcNs /*now*/) {}
  /// Bytes receiver i holds back (a `latency` fault): the epoch time they are due at, if any.
  [[nodiscard]] virtual std::optional<UtcNs> delayed_until(std::size_t /*i*/) const { return std::nullopt; }
  /// Receiver i's held-back bytes due by epoch time `t`; valid until the next call.
  [[nodiscard]] virtual std::string_view take_delayed(std::size_t /*i*/, UtcNs /*t*/) { return {}; }
};

/// Exit status of a run that stopped because every output is gone (a pipe's reader left).
inline constexpr int kExitOutputsGone = 1;
/// Exit status of a run in which no output took any epoch (every write failed: /dev/full, a full
/// disk); 0 is a run done, 2 a start-up failure.
inline constexpr int kExitNothingWritten = 3;

struct LoopOptions {
  /// A fleet in real time: compute each epoch ahead of its deadline, at most this long before
  /// (the latency). Empty: computed at the deadline.
  std::optional<std::chrono::nanoseconds> compute_ahead_within;
  /// Measure how late each epoch was handed to the sink (replay's summary).
  bool measure_send_delay = false;
  /// Counts the late epochs skipped as they happen, for another thread (the bench view); may be null.
  std::atomic<std::uint64_t>* late_epochs = nullptr;
};

struct LoopStats {
  std::uint64_t epochs_emitted = 0;       ///< epochs handed to the sink (each receiver's)
  std::uint64_t epochs_late_skipped = 0;  ///< epochs skipped because their time had long passed
  std::uint64_t clock_steps_back = 0;     ///< times the wall clock went back and the deadlines followed
  std::uint64_t reschedules = 0;          ///< waits cut short: a receiver's solution period changed
  /// With measure_send_delay: latest an epoch was handed to the sink after its deadline (an epoch
  /// whose time went back: after the previous epoch's deadline), and the sum (for the mean).
  std::chrono::nanoseconds worst_delay{0};
  std::chrono::nanoseconds total_delay{0};
  bool outputs_gone = false;  ///< stopped because every output is gone (Sink::all_gone)
};

/// The real ClockIo of a loop: polls every output's and input's descriptor and services those
/// with input.
[[nodiscard]] std::unique_ptr<SystemClockIo> make_loop_io(Sink& sink, EpochProducer& producer);

class EpochLoop {
 public:
  /// `pps`: drive this line's edges on the clock's deadlines (real time only); may be null.
  EpochLoop(EpochProducer& producer, Sink& sink, EpochClock& clock, LoopOptions options, PpsTimeline* pps = nullptr);
  ~EpochLoop();

  /// Runs until the producer has no epoch left, `stop` becomes true or every output is gone for
  /// good (stats().outputs_gone), then flushes the sink.
  void run(const std::atomic<bool>& stop);

  [[nodiscard]] const LoopStats& stats() const { return stats_; }
  /// After run(): 0, kExitOutputsGone or kExitNothingWritten, with an error line for either.
  [[nodiscard]] int exit_status() const;

 private:
  /// A clock with deadlines: follows a wall clock that went back, drives the PPS edges due first
  /// (when `sleep`), skips an epoch more than a period late, and (when `sleep`) waits for the
  /// deadline and looks again at how late the wake-up was.
  EpochWait wait_for_deadline(UtcNs t, bool sleep, const std::atomic<bool>& stop);
  /// The fleet's epoch in real time: compute ahead, write at the deadline (skip: woken more than a
  /// period after it; rescheduled: a receiver's period changed before the computing began).
  EpochWait run_ahead(std::int64_t k, UtcNs t, UtcNs deadline, const std::atomic<bool>& stop,
                      const std::function<bool()>& woken);
  /// Hands every active receiver's epoch `t` to the sink, computed now.
  void send(UtcNs t);
  /// When the producer wants it: reschedules at the epoch time of now, true.
  bool rescheduled(ClockIo& io);
  /// A `latency` fault: writes the held-back bytes due before wall time `until`, each at its own
  /// time (all of them, now, without a wall clock).
  void send_delayed(ClockIo* io, UtcNs until, const std::atomic<bool>& stop);
  /// One more epoch skipped late.
  void count_late() {
    ++stats_.epochs_late_skipped;
    if (options_.late_epochs) options_.late_epochs->fetch_add(1, std::memory_order_relaxed);
  }
  /// Writes positions [from, to) of the receivers in the order that starts with receiver `first`.
  void write_range(std::size_t first, std::size_t from, std::size_t to);

  EpochProducer& producer_;
  Sink& sink_;
  EpochClock& clock_;
  LoopOptions options_;
  PpsTimeline* pps_;
  std::vector<std::string_view> ahead_;  ///< the fleet's epoch, computed ahead
  /// A fleet: how long computing every epoch took lately (decaying maximum).
  std::chrono::nanoseconds compute_cost_{0};
  UtcNs latest_deadline_{UtcNs::min()};
  LoopStats stats_;
  std::unique_ptr<HelperWriter> helper_;  ///< last: stopped before what it writes goes
};

}  // namespace gpsemu
