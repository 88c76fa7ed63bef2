// What a u-blox knows about itself beside the fix, as the UBX messages report it: how long it has
// run and its time to first fix (NAV-STATUS), whether its time is valid, fully resolved and
// confirmed (NAV-PVT, NAV-TIMEUTC, NAV-TIMEGPS), its local clock's bias and drift (NAV-CLOCK) and
// its RF front end (MON-HW, MON-RF). Pure and deterministic given the seed.
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

/// The RF front end a u-blox reports in MON-HW and MON-RF: a clean steady state by default; a
/// fault (jamming, antenna short) changes these fields.
struct RfState {
  std::uint16_t noise_per_ms = 89;   ///< noise level of the correlators (MON-HW noisePerMS)
  std::uint16_t agc_count = 3140;    ///< automatic gain control, 0..8191 (MON-HW agcCnt)
  std::uint8_t jamming_indicator = 9;  ///< CW jamming indicator, 0 (none) .. 255 (strong)
  std::uint8_t jamming_state = 1;    ///< 0 unknown, 1 ok, 2 warning, 3 critical
  std::uint8_t antenna_status = 2;   ///< 0 init, 1 don't know, 2 ok, 3 short, 4 open
  std::uint8_t antenna_power = 1;    ///< 0 off, 1 on, 2 don't know
  /// NAV-STATUS spoofDetState: 0 unknown or off, 1 no spoofing indicated, 2 spoofing indicated,
  /// 3 multiple spoofing indications (a spoof fault sets it).
  std::uint8_t spoof_detection_state = 0;
};

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

  RfState& rf() { return rf_; }
  [[nodiscard]] const RfState& rf() const { return rf_; }
  /// A rover's position relative to its moving base (NAV-RELPOSNED), set each epoch by the channel.
  RelPosNed& relative_position() { return relpos_; }

 private:
  std::optional<nmea::UtcTime> power_on_;
  std::optional<nmea::UtcTime> last_;
  std::optional<std::chrono::milliseconds> ttff_;
  bool time_valid_ = false;
  std::optional<nmea::UtcTime> resolved_at_;  // the first fix since the time became valid
  ReceiverClock clock_;
  RfState rf_;
  RelPosNed relpos_;
};

}  // namespace gpsemu::ubx
