// VTG, GLL, ZDA and GST formatters (u-blox field layout), from fields.hpp's building blocks.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <string>

#include "nmea/fields.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {

constexpr double max_speed_knots = 1e6;
constexpr double kmh_per_mps = 3.6;
constexpr double max_sigma_m = 1000.0;  // GST values at or beyond this are left empty

std::string sigma_field(double sigma_m) { return fields::format_fixed(sigma_m, 3, max_sigma_m); }

}  // namespace

std::string format_vtg(const Fix& fix, const FormatOptions& options) {
  if (!fix.has_fix()) return frame(fmt::format("{}VTG,,T,,M,,N,,K,N", options.talker));
  const double speed_mps = std::fabs(fix.speed_mps);
  return frame(fmt::format("{}VTG,{},T,,M,{},N,{},K,{}", options.talker, fields::format_course(fix.course_deg_true),
                           fields::format_fixed(speed_mps * fields::knots_per_mps, 3, max_speed_knots),
                           fields::format_fixed(speed_mps * kmh_per_mps, 3, max_speed_knots * 2),
                           mode_indicator(fix.quality)));
}

std::string format_gll(const Fix& fix, const FormatOptions& options) {
  const std::string time = fix.time_valid ? fields::format_time_of_day(fix.time_utc, options.time_decimals) : "";
  if (!fix.has_fix()) return frame(fmt::format("{}GLL,,,,,{},V,N", options.talker, time));
  const fields::CoordinateFields lat = fields::format_latitude(fix.lat_deg, options.minute_decimals);
  const fields::CoordinateFields lon = fields::format_longitude(fix.lon_deg, options.minute_decimals);
  return frame(fmt::format("{}GLL,{},{},{},{},{},A,{}", options.talker, lat.value, lat.hemisphere, lon.value,
                           lon.hemisphere, time, mode_indicator(fix.quality)));
}

std::string format_zda(const Fix& fix, const FormatOptions& options) {
  using namespace std::chrono;
  if (!fix.time_valid) return frame(fmt::format("{}ZDA,,,,,00,00", options.talker));
  const year_month_day date{floor<days>(fix.time_utc)};
  return frame(fmt::format("{}ZDA,{},{:02},{:02},{:04},00,00", options.talker,
                           fields::format_time_of_day(fix.time_utc, options.time_decimals),
                           static_cast<unsigned>(date.day()), static_cast<unsigned>(date.month()),
                           static_cast<int>(date.year())));
}

std::string format_gst(const Fix& fix, const FormatOptions& options) {
  const std::string time = fix.time_valid ? fields::format_time_of_day(fix.time_utc, options.time_decimals) : "";
  if (!fix.has_fix()) return frame(fmt::format("{}GST,{},,,,,,,", options.talker, time));
  const double major_m = std::fmax(fix.sigma_lat_m, fix.sigma_lon_m);
  const double minor_m = std::fmin(fix.sigma_lat_m, fix.sigma_lon_m);
  const double orientation_deg = fix.sigma_lat_m >= fix.sigma_lon_m ? 0.0 : 90.0;
  return frame(fmt::format("{}GST,{},{},{},{},{},{},{},{}", options.talker, time, sigma_field(fix.range_rms_m),
                           sigma_field(major_m), sigma_field(minor_m), fields::format_fixed(orientation_deg, 1),
                           sigma_field(fix.sigma_lat_m), sigma_field(fix.sigma_lon_m),
                           sigma_field(fix.sigma_alt_m)));
}

}  // namespace gpsemu::nmea
