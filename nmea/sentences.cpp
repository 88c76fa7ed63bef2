// GGA and RMC formatters: field values from fields.hpp, framed with the checksum by frame().
// (VTG, GLL, ZDA, GST: sentences_more.cpp; GSA, GSV: satellites.cpp; the epoch: epoch.cpp.)
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

// Largest magnitudes that still fit their field; beyond them the field is left empty.
constexpr double max_alt_m = 1e6;
constexpr double max_geoid_sep_m = 1e4;
constexpr double max_speed_knots = 1e6;

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
  const bool two_d = fix.dimension == FixDimension::two_d;  // no altitude in a 2-D fix
  const std::string alt = two_d ? std::string{} : fields::format_fixed(fix.alt_msl_m, 1, max_alt_m);
  const std::string sep = two_d ? std::string{} : fields::format_fixed(fix.geoid_sep_m, 1, max_geoid_sep_m);
  return frame(fmt::format("{}GGA,{},{},{},{},{},{},{:02},{},{},{},,", options.talker, time, lat.value,
                           lat.hemisphere, lon.value, lon.hemisphere, static_cast<int>(fix.quality),
                           satellites, fields::format_fixed(hdop, 2, 100.0),
                           with_unit(alt, "M"), with_unit(sep, "M")));
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
  const double speed_knots = std::fabs(fix.speed_mps) * fields::knots_per_mps;
  return frame(fmt::format("{}RMC,{},A,{},{},{},{},{},{},{},,,{}{}", options.talker, time, lat.value,
                           lat.hemisphere, lon.value, lon.hemisphere,
                           fields::format_fixed(speed_knots, 3, max_speed_knots),
                           fields::format_course(fix.course_deg_true), date, mode_indicator(fix.quality),
                           nav_status));
}

}  // namespace gpsemu::nmea
