// The serial line budget check at start-up (docs/design.md "Serial line budget"): the widest epoch of
// the configured sentences (nmea::line_budget on nmea::widest_fix) against what a serial output's
// baud carries within nmea::kLineBudgetMargin. A configuration that cannot fit is refused with a
// message naming a standard baud that would.
#pragma once

#include <cstddef>

#include "nmea/fix.hpp"
#include "transport/output_spec.hpp"

namespace gpsemu {

/// Satellites in view assumed for the worst-case epoch (GSV lists them, four a sentence), 12 used.
inline constexpr int kBudgetSatellitesInView = 20;

/// Bytes of the widest epoch `format` produces with `satellites_in_view` satellites, 12 used.
[[nodiscard]] std::size_t worst_case_epoch_bytes(const nmea::FormatOptions& format,
                                                 int satellites_in_view = kBudgetSatellitesInView);

/// For a serial output: throws std::runtime_error naming the spec, the bytes per second needed
/// and available, a standard baud that fits and the highest rate that fits at this baud, when
/// `epoch_bytes` at `rate_hz` cannot fit in nmea::kLineBudgetMargin of the line. Other kinds: nothing.
void check_serial_line_budget(const transport::OutputSpec& spec, std::size_t epoch_bytes, double rate_hz);

}  // namespace gpsemu
