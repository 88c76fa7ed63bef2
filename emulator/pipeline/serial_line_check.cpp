#include "emulator/pipeline/serial_line_check.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <string>

#include "nmea/line_budget.hpp"

namespace gpsemu {

std::size_t worst_case_epoch_bytes(const nmea::FormatOptions& format,
                                   std::span<const nmea::SystemSatellites> in_view_by_system, int satellites_used) {
  return nmea::line_budget(format, in_view_by_system, satellites_used, 1.0).bytes_per_epoch;
}

void check_serial_line_budget(const transport::OutputSpec& spec, std::size_t epoch_bytes, double rate_hz) {
  if (spec.kind != transport::OutputKind::serial) return;
  const int baud = spec.baud_bps != 0 ? spec.baud_bps : nmea::kDefaultBaud;
  const nmea::LineBudget b = nmea::line_budget(epoch_bytes, rate_hz);
  if (b.fits(baud, nmea::kLineBudgetMargin)) return;
  const double usable_bytes_per_s = nmea::line_bytes_per_second(baud) * nmea::kLineBudgetMargin;
  // The highest rate the emulator offers (1..50 Hz, or a whole number of seconds) that fits.
  std::string slower = "no rate fits at this baud";
  for (double r = 50.0; r >= 0.1;) {
    if (static_cast<double>(epoch_bytes) * r <= usable_bytes_per_s) {
      slower = fmt::format("or at most {} Hz at {} baud", r, baud);
      break;
    }
    r = r > 1.0 ? r - 1.0 : (r == 1.0 ? 0.5 : r == 0.5 ? 0.25 : r == 0.25 ? 0.2 : r == 0.2 ? 0.1 : 0.0);
  }
  transport::OutputSpec faster = spec;
  std::string fix_it;
  if (const int fitting_baud = nmea::smallest_standard_baud(b, nmea::kLineBudgetMargin); fitting_baud != 0) {
    faster.baud_bps = fitting_baud;
    fix_it = fmt::format("use {} baud or more ({}), {}", fitting_baud, to_string(faster), slower);
  } else {
    fix_it = fmt::format("no standard baud up to 921600 carries it: lower --rate or drop sentences ({})", slower);
  }
  throw std::runtime_error(fmt::format(
      "{}: {} Hz x {} bytes an epoch (widest epoch of the configured sentences) = {:.0f} bytes/s does not fit "
      "{} baud (8N1 carries {:.0f} bytes/s, {:.0f} within the {:.0f}% margin); {}",
      to_string(spec), rate_hz, epoch_bytes, b.bytes_per_second, baud, nmea::line_bytes_per_second(baud),
      usable_bytes_per_s, nmea::kLineBudgetMargin * 100.0, fix_it));
}

}  // namespace gpsemu
