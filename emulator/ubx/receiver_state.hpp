// What a u-blox knows about itself beside the fix, as the UBX messages report it: how long it has
// run and its time to first fix (NAV-STATUS), whether its time is valid, fully resolved and
// confirmed (NAV-PVT, NAV-TIMEUTC, NAV-TIMEGPS) and its local clock's bias and drift (NAV-CLOCK);
// the RF front end and the relative position come with each epoch (emulator/model/epoch.hpp). Pure and deterministic given the seed.
//
// Time, as a receiver learns it: without a satellite (cold start, outage) nothing is valid; the
// first tracked satellite gives time of week and week (validDate, validTime); the first fix after
// it resolves UTC (fullyResolved, validUTC, leap seconds); the time is confirmed (confirmedDate,
// confirmedTime) kConfirmDelay after that fix. A receiver whose first solution already has a fix
// was hot: it was switched on kHotStartTtff earlier and its time is valid and confirmed at once.
//
// The clock: a TCXO whose frequency offset (the drift, ns/s) wanders as a first-order
// Gauss-Markov process around a per-unit offset drawn from the seed; the bias integrates it and,
// as on a u-blox (RXM-RAWX's clkReset), is stepped by whole milliseconds when it leaves +-0.5 ms.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "emulator/ubx/relposned.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::ubx {

/// The RF front end MON-HW and MON-RF report: the epoch's (emulator/model/epoch.hpp).
using RfState = gpsemu::RfState;

/// The receiver clock (NAV-CLOCK).
struct ClockState {
  std::int32_t bias_ns = 0;         ///< clkB: receiver clock minus GPS time (ns)
  std::int32_t drift_ns_per_s = 0;  ///< clkD (ns/s)
  std::uint32_t time_accuracy_ns = 20;         ///< tAcc (ns)
  std::uint32_t frequency_accuracy_ps_per_s = 500;  ///< fAcc (ps/s)
};

/// How much of the time a receiver knows.
struct TimeValidity {
  bool valid = true;      ///< time of week and week known (validDate, validTime, TOW/WKN set)
  bool resolved = true;   ///< UTC fully resolved (fullyResolved, validUTC, leap seconds valid)
  bool confirmed = true;  ///< date and time confirmed (confirmedDate, confirmedTime)
};

/// Time to first fix of a hot start (the receiver was on before the first solution).
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
  double gaussian();
  std::uint64_t seed_;
  std::uint64_t state_ = 0;
  double unit_offset_ns_per_s_ = 0.0;  // the oscillator's own offset
  double drift_ns_per_s_ = 0.0;
  double bias_ns_ = 0.0;
};

/// One u-blox's state across solutions.
class ReceiverState {
 public:
  explicit ReceiverState(std::uint64_t seed) : clock_(seed) {}

  /// The state at the solution of `fix` (call once per solution, in time order).
  struct AtSolution {
    std::chrono::milliseconds since_start{0};       ///< msss
    std::chrono::milliseconds time_to_first_fix{0};  ///< ttff; 0 before the first fix
    TimeValidity time;
    ClockState clock;
  };
  AtSolution at(const nmea::Fix& fix);
  /// CFG-RST: the receiver starts again at its next solution (msss 0, no fix yet, nothing valid).
  void restart();


 private:
  std::optional<nmea::UtcTime> power_on_;
  std::optional<nmea::UtcTime> last_;
  std::optional<std::chrono::milliseconds> ttff_;
  bool time_valid_ = false;
  std::optional<nmea::UtcTime> resolved_at_;  // the first fix since the time became valid
  ReceiverClock clock_;
};

}  // namespace gpsemu::ubx
