#include "nmea/line_budget.hpp"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "nmea/sentences.hpp"

namespace gpsemu::nmea {

bool is_standard_baud(int baud_bps) {
  return std::find(kStandardBauds.begin(), kStandardBauds.end(), baud_bps) != kStandardBauds.end();
}

std::string standard_bauds_text() { return fmt::format("{}", fmt::join(kStandardBauds, ", ")); }

LineBudget line_budget(std::size_t bytes_per_epoch, double rate_hz) {
  LineBudget budget;
  budget.bytes_per_epoch = bytes_per_epoch;
  budget.bytes_per_second = static_cast<double>(bytes_per_epoch) * rate_hz;
  budget.min_baud = 10.0 * budget.bytes_per_second;
  return budget;
}

Fix widest_fix(int satellites_in_view, int satellites_used) {
  const SystemSatellites gps{GnssSystem::gps, satellites_in_view};
  return widest_fix(std::span<const SystemSatellites>(&gps, 1), satellites_used);
}

Fix widest_fix(std::span<const SystemSatellites> systems, int satellites_used) {
  using namespace std::chrono;
  Fix fix;
  fix.time_utc = UtcTime{sys_days{year{2099} / December / 31}} + hours{23} + minutes{59} + seconds{59} +
                 milliseconds{999};
  fix.quality = FixQuality::rtk_float;
  fix.dimension = FixDimension::three_d;
  fix.lat_deg = -(89.0 + 59.99999 / 60.0);
  fix.lon_deg = -(179.0 + 59.99999 / 60.0);
  fix.alt_msl_m = -12345.6;  // 8 characters: wider than any altitude up to 99 999.9 m
  fix.geoid_sep_m = -106.9;
  fix.speed_mps = 500.0;
  fix.course_deg_true = 359.99;
  fix.heading_deg_true = 359.99;
  fix.hdop = fix.vdop = fix.pdop = 99.99;
  fix.sigma_lat_m = fix.sigma_lon_m = fix.sigma_alt_m = fix.range_rms_m = 999.999;
  // RTK adds GGA's differential fields (docs/rtk.md): the widest age and a 4-digit station id.
  fix.diff_age_s = 999.9;
  fix.diff_station_id = 4095;
  int total = 0;
  for (const SystemSatellites& s : systems) total += std::max(s.in_view, 0);
  total = std::min(total, static_cast<int>(max_satellites));
  const int used = std::clamp(satellites_used, 0, total);
  // The used satellites spread over the systems in proportion, as a receiver's solution uses them
  // (each system's GSA lists its own).
  int n = 0, marked = 0;
  for (const SystemSatellites& s : systems) {
    const int in_view = std::min(std::max(s.in_view, 0), total - n);
    const int share = total == 0 ? 0 : std::min(in_view, (used * (n + in_view) + total - 1) / total - marked);
    for (int k = 0; k < in_view; ++k, ++n) {
      // Two-digit IDs, as every system's are in NMEA 4.1 (GLONASS 65..96).
      const int id = s.system == GnssSystem::glonass ? 96 : 32;
      fix.satellites[static_cast<std::size_t>(n)] = {id, 90, 359, 99, k < share, s.system, 32};
    }
    marked += share;
  }
  fix.satellites_in_view = n;
  fix.satellites_used = marked;
  return fix;
}

LineBudget line_budget(const FormatOptions& options, int satellites_in_view, int satellites_used, double rate_hz) {
  std::string epoch;
  append_epoch(widest_fix(satellites_in_view, satellites_used), options, epoch);
  return line_budget(epoch.size(), rate_hz);
}

LineBudget line_budget(const FormatOptions& options, std::span<const SystemSatellites> systems, int satellites_used,
                       double rate_hz) {
  std::string epoch;
  append_epoch(widest_fix(systems, satellites_used), options, epoch);
  return line_budget(epoch.size(), rate_hz);
}

int smallest_standard_baud(const LineBudget& budget, double margin) {
  for (const int baud : kStandardBauds) {
    if (budget.fits(baud, margin)) return baud;
  }
  return 0;
}

}  // namespace gpsemu::nmea
