// The epoch clock as a user names it (--clock realtime | scaled:K | fast | lockstep): the value, its
// parser and its text. The pipeline builds the clock it names (emulator/pipeline/clock.hpp).
#pragma once

#include <string>
#include <string_view>

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

}  // namespace gpsemu
