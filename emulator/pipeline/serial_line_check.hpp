// The serial line budget check at start-up (docs/design.md "Serial line budget"): the widest epoch of
// the configured sentences (nmea::line_budget on nmea::widest_fix) against what a serial output's
// baud carries within nmea::kLineBudgetMargin. A configuration that cannot fit is refused with a
// message naming a standard baud that would.
#pragma once

#include <cstddef>
#include <span>

#include "nmea/fix.hpp"
#include "nmea/line_budget.hpp"
#include "transport/output_spec.hpp"

namespace gpsemu {

/// Bytes of the widest epoch `format` produces for the satellites `in_view_by_system` (each system
/// in its own GSV group and GSA, as the writer lists them: the model's worst case of
/// resolve_geometry, Geometry::in_view_by_system), the first `satellites_used` of them used.
[[nodiscard]] std::size_t worst_case_epoch_bytes(const nmea::FormatOptions& format,
                                                 std::span<const nmea::SystemSatellites> in_view_by_system,
                                                 int satellites_used);

/// For a serial output: throws std::runtime_error naming the spec, the bytes per second needed
/// and available, a standard baud that fits and the highest rate that fits at this baud, when
/// `epoch_bytes` at `rate_hz` cannot fit in nmea::kLineBudgetMargin of the line. Other kinds: nothing.
void check_serial_line_budget(const transport::OutputSpec& spec, std::size_t epoch_bytes, double rate_hz);

}  // namespace gpsemu
