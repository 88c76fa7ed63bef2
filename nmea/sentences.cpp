// GGA and RMC formatters: field values from fields.hpp, framed with the checksum by frame().
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "nmea/fields.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {

constexpr double knots_per_mps = 3600.0 / 1852.0;  // 1 kn = 1852 m / 3600 s

// Largest magnitudes that still fit their field; beyond them the field is left empty.
constexpr double max_alt_m = 1e6;
constexpr double max_geoid_sep_m = 1e4;
constexpr double max_speed_knots = 1e6;

// "c.cc" degrees true, normalised into [0, 360) after rounding (359.999 is "0.00"); empty when
// unknown.
std::string format_course(const std::optional<double>& course_deg_true) {
  if (!course_deg_true || !std::isfinite(*course_deg_true)) return {};
  const double normalised_deg = std::fmod(*course_deg_true, 360.0);
  std::int64_t centidegrees = std::llround(normalised_deg * 100.0) % 36000;
  if (centidegrees < 0) centidegrees += 36000;
  return fmt::format("{}.{:02}", centidegrees / 100, centidegrees % 100);
}

// A value followed by its unit field ("545.4,M"), or two empty fields.
std::string with_unit(const std::string& value, std::string_view unit) {
  return fmt::format("{},{}", value, value.empty() ? std::string_view{} : unit);
}

}  // namespace

char mode_indicator(FixQuality quality) {
  switch (quality) {
    case FixQuality::none: return 'N';
    case FixQuality::gps: return 'A';
    case FixQuality::dgps: return 'D';
    case FixQuality::pps: return 'P';
    case FixQuality::rtk_fixed: return 'R';
    case FixQuality::rtk_float: return 'F';
    case FixQuality::estimated: return 'E';
  }
  return 'N';
}

std::string format_gga(const Fix& fix, const FormatOptions& options) {
  const std::string time = fields::format_time_of_day(fix.time_utc, options.time_decimals);
  if (!fix.has_fix()) return frame(fmt::format("{}GGA,{},,,,,0,00,99.99,,,,,,", options.talker, time));

  const fields::CoordinateFields lat = fields::format_latitude(fix.lat_deg, options.minute_decimals);
  const fields::CoordinateFields lon = fields::format_longitude(fix.lon_deg, options.minute_decimals);
  const int satellites = std::clamp(fix.satellites_used, 0, 99);
  const double hdop = std::clamp(fix.hdop, 0.0, 99.99);
  return frame(fmt::format("{}GGA,{},{},{},{},{},{},{:02},{},{},{},,", options.talker, time, lat.value,
                           lat.hemisphere, lon.value, lon.hemisphere, static_cast<int>(fix.quality),
                           satellites, fields::format_fixed(hdop, 2, 100.0),
                           with_unit(fields::format_fixed(fix.alt_msl_m, 1, max_alt_m), "M"),
                           with_unit(fields::format_fixed(fix.geoid_sep_m, 1, max_geoid_sep_m), "M")));
}

std::string format_rmc(const Fix& fix, const FormatOptions& options) {
  const std::string time = fields::format_time_of_day(fix.time_utc, options.time_decimals);
  const std::string date = fields::format_date_ddmmyy(fix.time_utc);
  const std::string_view nav_status = options.version == NmeaVersion::v4_1 ? ",V" : "";
  if (!fix.has_fix()) {
    return frame(fmt::format("{}RMC,{},V,,,,,,,{},,,N{}", options.talker, time, date, nav_status));
  }

  const fields::CoordinateFields lat = fields::format_latitude(fix.lat_deg, options.minute_decimals);
  const fields::CoordinateFields lon = fields::format_longitude(fix.lon_deg, options.minute_decimals);
  const double speed_knots = std::fabs(fix.speed_mps) * knots_per_mps;
  return frame(fmt::format("{}RMC,{},A,{},{},{},{},{},{},{},,,{}{}", options.talker, time, lat.value,
                           lat.hemisphere, lon.value, lon.hemisphere,
                           fields::format_fixed(speed_knots, 3, max_speed_knots),
                           format_course(fix.course_deg_true), date, mode_indicator(fix.quality),
                           nav_status));
}

}  // namespace gpsemu::nmea
