// PPS: a pulse whose leading edge marks each whole UTC second (docs/design.md "Timing semantics").
// A small interface for the line that carries it — the runner calls set() at each edge's
// absolute time, in one timeline with the epoch writes — and the pure pulse-train arithmetic.
// Backends: a GPIO line through libgpiod (gpio_pps.hpp), a UART modem line RTS/DTR on the serial
// output (modem_pps.hpp); a recording fake for tests (recording_pps.hpp). The base class applies
// the polarity, counts, and rate-limits failure reports like Output does.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

#include "emulator/common/log_limit.hpp"
#include "emulator/config/spec/pps_spec.hpp"

namespace gpsemu::transport {

/// Wall-clock time (CLOCK_REALTIME, UTC), nanoseconds.
using PpsTime = std::chrono::sys_time<std::chrono::nanoseconds>;

/// The line's level during the pulse.
enum class PpsPolarity {
  active_high,  ///< high during the pulse: GPIO value 1, modem line asserted (default)
  active_low,   ///< low during the pulse: GPIO value 0, modem line cleared
};

struct PpsStats {
  std::uint64_t leading_edges = 0;   ///< pulses started
  std::uint64_t trailing_edges = 0;  ///< pulses ended
  std::uint64_t failures = 0;        ///< set() calls the backend could not carry out
};

class PpsLine {
 public:
  explicit PpsLine(PpsPolarity polarity) : polarity_(polarity) {}
  virtual ~PpsLine() = default;
  PpsLine(const PpsLine&) = delete;
  PpsLine& operator=(const PpsLine&) = delete;

  /// Starts (`pulse_on` true: the leading edge) or ends the pulse now. The runner calls it at the
  /// edge's absolute time. Never blocks; a failure is counted, reported at most once a second,
  /// and returns false.
  bool set(bool pulse_on);

  /// "gpio /dev/gpiochip0 line 18", "modem RTS on /dev/ttyUSB0", "recording".
  [[nodiscard]] virtual std::string describe() const = 0;

  [[nodiscard]] bool pulse_on() const { return pulse_on_; }
  [[nodiscard]] PpsPolarity polarity() const { return polarity_; }
  [[nodiscard]] const PpsStats& stats() const { return stats_; }

 protected:
  /// Backend hook: drive the line to `level` (true: high / asserted) now. Returns false with a
  /// reason in `error_text` when it cannot.
  virtual bool drive(bool level, std::string& error_text) = 0;
  /// The level of the line between pulses, for backends that set it when they open the line.
  [[nodiscard]] bool idle_level() const { return polarity_ == PpsPolarity::active_low; }

 private:
  PpsPolarity polarity_;
  bool pulse_on_ = false;
  PpsStats stats_;
  LogLimit failure_log_{1};  ///< "edge not driven" lines: at most one a second
};

/// One edge of the pulse train.
struct PpsEdge {
  PpsTime time{};        ///< when it is due (wall clock)
  bool leading = false;  ///< leading edge (at a whole second) or trailing (at second + width)

  friend bool operator==(const PpsEdge&, const PpsEdge&) = default;
};

/// The first edge at or after `t` of the train whose leading edges lie at every whole second and
/// trailing edges `width` later; `width` in (0, 1 s).
[[nodiscard]] PpsEdge first_pps_edge_at_or_after(PpsTime t, std::chrono::nanoseconds width);
/// The edge after `edge` in the same train.
[[nodiscard]] PpsEdge next_pps_edge(const PpsEdge& edge, std::chrono::nanoseconds width);

}  // namespace gpsemu::transport
