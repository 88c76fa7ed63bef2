#include "transport/serial_budget.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace gpsemu::transport {

bool is_standard_baud(int baud_bps) {
  return std::find(kStandardBauds.begin(), kStandardBauds.end(), baud_bps) != kStandardBauds.end();
}

LineBudget line_budget(int baud_bps, std::size_t epoch_bytes, double rate_hz, double margin) {
  LineBudget b;
  b.needed_bytes_per_s = static_cast<double>(epoch_bytes) * rate_hz;
  b.line_bytes_per_s = line_bytes_per_second(baud_bps);
  b.usable_bytes_per_s = b.line_bytes_per_s * margin;
  b.fits = b.needed_bytes_per_s <= b.usable_bytes_per_s;
  for (const int baud : kStandardBauds) {
    if (b.needed_bytes_per_s <= line_bytes_per_second(baud) * margin) {
      b.fitting_baud = baud;
      break;
    }
  }
  return b;
}

std::string standard_bauds_text() { return fmt::format("{}", fmt::join(kStandardBauds, ", ")); }

}  // namespace gpsemu::transport
