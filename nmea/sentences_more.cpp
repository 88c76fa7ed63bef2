// ZDA and GST formatters (u-blox field layout), from fields.hpp's building blocks.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <string>

#include "nmea/fields.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {

constexpr double max_sigma_m = 1000.0;  // GST values at or beyond this are left empty

std::string sigma_field(double sigma_m) { return fields::format_fixed(sigma_m, 3, max_sigma_m); }

}  // namespace

std::string format_zda(const Fix& fix, const FormatOptions& options) {
  using namespace std::chrono;
  if (!fix.time_valid) return frame(fmt::format("{}ZDA,,,,,00,00", options.talker));
  const year_month_day date{floor<days>(fix.time_utc)};
  return frame(fmt::format("{}ZDA,{},{:02},{:02},{:04},00,00", options.talker,
                           fields::format_time_of_day(fix.time_utc, options.time_decimals, fix.leap.in_second_60),
                           static_cast<unsigned>(date.day()), static_cast<unsigned>(date.month()),
                           static_cast<int>(date.year())));
}

std::string format_gst(const Fix& fix, const FormatOptions& options) {
  const std::string time =
      fix.time_valid ? fields::format_time_of_day(fix.time_utc, options.time_decimals, fix.leap.in_second_60) : "";
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
