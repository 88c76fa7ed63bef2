#include "emulator/pipeline/serial_line_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <stdexcept>
#include <string>

#include "emulator/pipeline/epoch_text.hpp"
#include "transport/serial_budget.hpp"

namespace gpsemu {
namespace {

/// Fills what only newer Fix versions have (satellites in view for GSV/GSA, GST's range RMS),
/// so the measurement follows the sentence formatters as they grow.
template <class F>
void fill_optional_fields(F& fix, int satellites_in_view, int satellites_used) {
  if constexpr (requires { fix.satellites_in_view; fix.satellites[0].snr_dbhz; fix.satellites[0].used; }) {
    fix.satellites_in_view = std::clamp(satellites_in_view, 0, static_cast<int>(fix.satellites.size()));
    for (int i = 0; i < fix.satellites_in_view; ++i) {
      auto& s = fix.satellites[static_cast<std::size_t>(i)];
      s.prn = 32;
      s.elevation_deg = 90;
      s.azimuth_deg = 359;
      s.snr_dbhz = 99;
      s.used = i < satellites_used;
    }
  }
  if constexpr (requires { fix.range_rms_m; }) fix.range_rms_m = 999.999;
}

}  // namespace

std::size_t worst_case_epoch_bytes(const nmea::FormatOptions& format, int satellites_in_view) {
  using namespace std::chrono;
  nmea::Fix fix;
  fix.time_utc = nmea::UtcTime{sys_days{year{2099} / December / 31}} + hours{23} + minutes{59} + seconds{59} +
                 milliseconds{999};
  fix.quality = nmea::FixQuality::rtk_float;
  fix.dimension = nmea::FixDimension::three_d;
  fix.lat_deg = -(89.0 + 59.99999 / 60.0);
  fix.lon_deg = -(179.0 + 59.99999 / 60.0);
  fix.alt_msl_m = -12345.6;
  fix.geoid_sep_m = -106.9;
  fix.speed_mps = 500.0;
  fix.course_deg_true = 359.99;
  fix.satellites_used = 12;
  fix.hdop = fix.vdop = fix.pdop = 99.99;
  fix.sigma_lat_m = fix.sigma_lon_m = fix.sigma_alt_m = 999.999;
  fill_optional_fields(fix, satellites_in_view, fix.satellites_used);
  std::string text;
  format_epoch(fix, format, text);
  return text.size();
}

void check_serial_line_budget(const transport::OutputSpec& spec, std::size_t epoch_bytes, double rate_hz) {
  if (spec.kind != transport::OutputKind::serial) return;
  const int baud = spec.baud_bps != 0 ? spec.baud_bps : transport::kDefaultBaud;
  const transport::LineBudget b = transport::line_budget(baud, epoch_bytes, rate_hz);
  if (b.fits) return;
  // The highest rate the emulator offers (1..50 Hz, or a whole number of seconds) that fits.
  std::string slower = "no rate fits at this baud";
  for (double r = 50.0; r >= 0.1;) {
    if (static_cast<double>(epoch_bytes) * r <= b.usable_bytes_per_s) {
      slower = fmt::format("or at most {} Hz at {} baud", r, baud);
      break;
    }
    r = r > 1.0 ? r - 1.0 : (r == 1.0 ? 0.5 : r == 0.5 ? 0.25 : r == 0.25 ? 0.2 : r == 0.2 ? 0.1 : 0.0);
  }
  transport::OutputSpec faster = spec;
  std::string fix_it;
  if (b.fitting_baud) {
    faster.baud_bps = *b.fitting_baud;
    fix_it = fmt::format("use {} baud or more ({}), {}", *b.fitting_baud, to_string(faster), slower);
  } else {
    fix_it = fmt::format("no standard baud up to 921600 carries it: lower --rate or drop sentences ({})", slower);
  }
  throw std::runtime_error(fmt::format(
      "{}: {} Hz x {} bytes an epoch (widest epoch of the configured sentences) = {:.0f} bytes/s does not fit "
      "{} baud (8N1 carries {:.0f} bytes/s, {:.0f} within the {:.0f}% margin); {}",
      to_string(spec), rate_hz, epoch_bytes, b.needed_bytes_per_s, baud, b.line_bytes_per_s, b.usable_bytes_per_s,
      transport::kLineBudgetMargin * 100.0, fix_it));
}

}  // namespace gpsemu
