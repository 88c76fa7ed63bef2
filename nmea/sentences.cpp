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
#include "nmea/text_append.hpp"

namespace gpsemu::nmea {
namespace {

// Largest magnitudes that still fit their field; beyond them the field is left empty.
constexpr double max_alt_m = 1e6;
constexpr double max_geoid_sep_m = 1e4;
constexpr double max_speed_knots = 1e6;

// Appends ",value,unit" ("545.4,M"), or two empty fields when the value is empty.
void append_with_unit(std::string& out, const std::string& value, char unit) {
  out += ',';
  out += value;
  out += ',';
  if (!value.empty()) out += unit;
}

// Appends ",value,hemisphere" of a latitude or longitude.
void append_coordinate(std::string& out, const fields::CoordinateFields& coordinate) {
  out += ',';
  out += coordinate.value;
  out += ',';
  out += coordinate.hemisphere;
}

// "$" + talker + type: the start of every sentence (the body ends with close_sentence).
std::string start_sentence(const FormatOptions& options, std::string_view type) {
  std::string out;
  out.reserve(96);  // GGA and RMC fit in 82 characters
  out += '$';
  out += options.talker;
  out += type;
  return out;
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
  std::string out = start_sentence(options, "GGA,");
  out += time;
  if (!fix.has_fix()) {
    out += ",,,,,0,00,99.99,,,,,,";
    text::close_sentence(out);
    return out;
  }

  const fields::CoordinateFields lat = fields::format_latitude(fix.lat_deg, options.minute_decimals);
  const fields::CoordinateFields lon = fields::format_longitude(fix.lon_deg, options.minute_decimals);
  const int satellites = std::clamp(fix.satellites_used, 0, 99);
  const double hdop = std::clamp(fix.hdop, 0.0, 99.99);
  const bool two_d = fix.dimension == FixDimension::two_d;  // no altitude in a 2-D fix
  const std::string alt = two_d ? std::string{} : fields::format_fixed(fix.alt_msl_m, 1, max_alt_m);
  const std::string sep = two_d ? std::string{} : fields::format_fixed(fix.geoid_sep_m, 1, max_geoid_sep_m);
  append_coordinate(out, lat);
  append_coordinate(out, lon);
  out += ',';
  text::append_uint(out, static_cast<std::uint64_t>(static_cast<int>(fix.quality)));
  out += ',';
  text::append_uint(out, static_cast<std::uint64_t>(satellites), 2);
  out += ',';
  out += fields::format_fixed(hdop, 2, 100.0);
  append_with_unit(out, alt, 'M');
  append_with_unit(out, sep, 'M');
  out += ",,";
  text::close_sentence(out);
  return out;
}

std::string format_rmc(const Fix& fix, const FormatOptions& options) {
  const std::string time = fields::format_time_of_day(fix.time_utc, options.time_decimals);
  const std::string date = fields::format_date_ddmmyy(fix.time_utc);
  const std::string_view nav_status = options.version == NmeaVersion::v4_1 ? ",V" : "";
  std::string out = start_sentence(options, "RMC,");
  out += time;
  if (!fix.has_fix()) {
    out += ",V,,,,,,,";
    out += date;
    out += ",,,N";
    out += nav_status;
    text::close_sentence(out);
    return out;
  }

  const fields::CoordinateFields lat = fields::format_latitude(fix.lat_deg, options.minute_decimals);
  const fields::CoordinateFields lon = fields::format_longitude(fix.lon_deg, options.minute_decimals);
  const double speed_knots = std::fabs(fix.speed_mps) * fields::knots_per_mps;
  out += ",A";
  append_coordinate(out, lat);
  append_coordinate(out, lon);
  out += ',';
  out += fields::format_fixed(speed_knots, 3, max_speed_knots);
  out += ',';
  out += fields::format_course(fix.course_deg_true);
  out += ',';
  out += date;
  out += ",,,";
  out += mode_indicator(fix.quality);
  out += nav_status;
  text::close_sentence(out);
  return out;
}

}  // namespace gpsemu::nmea
