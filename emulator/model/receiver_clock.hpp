// What a receiver knows about itself beside the fix (model/epoch.hpp: ReceiverStatus): how long it
// has run and its time to first fix, whether its time is valid, fully resolved and confirmed, and
// its local clock's bias and drift. The last stage of an epoch, after the faults (a jam that takes
// every satellite takes the time too); a receiver's protocols report it (u-blox NAV-STATUS,
// NAV-PVT, NAV-TIMEUTC, NAV-TIMEGPS, NAV-CLOCK). Pure and deterministic given the seed.
//
// Time, as a receiver learns it: without a satellite (cold start, outage) nothing is valid; the
// first tracked satellite gives time of week and week (validDate, validTime); the first fix after
// it resolves UTC (fullyResolved, validUTC, leap seconds); the time is confirmed (confirmedDate,
// confirmedTime) kConfirmDelay after that fix. A receiver whose first epoch already has a fix
// was hot: it was switched on kHotStartTtff earlier and its time is valid and confirmed at once.
//
// The clock: a TCXO whose frequency offset (the drift, ns/s) wanders as a first-order
// Gauss-Markov process around a per-unit offset drawn from the seed; the bias integrates it and,
// as on a u-blox (RXM-RAWX's clkReset), is stepped by whole milliseconds when it leaves +-0.5 ms.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "emulator/model/epoch.hpp"
#include "emulator/model/noise/rng.hpp"
#include "nmea/fix.hpp"

namespace gpsemu {

/// Time to first fix of a hot start (the receiver was on before the first epoch).
inline constexpr std::chrono::milliseconds kHotStartTtff{1000};
/// Time from the first fix to confirmed date and time.
inline constexpr std::chrono::milliseconds kConfirmDelay{2000};

/// A drifting, steered receiver clock, deterministic given the seed.
class ReceiverClock {
 public:
  explicit ReceiverClock(std::uint64_t seed);
  /// Advances by `dt` (>= 0) and returns the state; `has_fix` sets the accuracies.
  ClockState step(std::chrono::milliseconds dt, bool has_fix);
  /// A reset: the clock starts again from the seed.
  void restart();

 private:
  noise::Rng rng_;  ///< its own stream of the run's seed
  double unit_offset_ns_per_s_ = 0.0;  // the oscillator's own offset
  double drift_ns_per_s_ = 0.0;
  double bias_ns_ = 0.0;
  std::chrono::milliseconds step_dt_{-1};  ///< the interval step_a_ and step_b_ are for
  double step_a_ = 0.0, step_b_ = 0.0;
};

/// One receiver's status across epochs.
class ReceiverStatusTracker {
 public:
  explicit ReceiverStatusTracker(std::uint64_t seed) : clock_(seed) {}

  /// The status at the epoch of `fix` (the fix after the faults; once per epoch the receiver
  /// reports, in time order).
  [[nodiscard]] ReceiverStatus at(const nmea::Fix& fix);
  /// A cold start or reset: the receiver starts again at its next epoch (0 run time, no fix yet,
  /// nothing valid).
  void restart();

 private:
  std::optional<nmea::UtcTime> power_on_;
  std::optional<nmea::UtcTime> last_;
  std::optional<std::chrono::milliseconds> ttff_;
  bool time_valid_ = false;
  std::optional<nmea::UtcTime> resolved_at_;  // the first fix since the time became valid
  ReceiverClock clock_;
};

}  // namespace gpsemu
