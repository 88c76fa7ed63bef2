#include "nmea/fields.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string_view>

namespace gpsemu::nmea::fields {
namespace {

constexpr std::int64_t pow10(int exponent) {
  std::int64_t result = 1;
  for (int i = 0; i < exponent; ++i) result *= 10;
  return result;
}

// |angle_deg| in units of 10^-decimals minutes, rounded once, then split with integers.
CoordinateFields format_angle(double angle_deg, int minute_decimals, int degree_digits,
                              std::string_view positive, std::string_view negative) {
  const int decimals = std::clamp(minute_decimals, 1, 8);
  const std::int64_t units_per_minute = pow10(decimals);
  const std::int64_t units_per_degree = 60 * units_per_minute;
  // |angle| <= 180 and decimals <= 8: at most 1.08e12 units, exact in a double and an int64.
  const std::int64_t units = std::llround(std::fabs(angle_deg) * static_cast<double>(units_per_degree));
  const std::int64_t degrees = units / units_per_degree;
  const std::int64_t minute_units = units % units_per_degree;
  CoordinateFields out;
  out.value = fmt::format("{:0{}}{:02}.{:0{}}", degrees, degree_digits, minute_units / units_per_minute,
                          minute_units % units_per_minute, decimals);
  out.hemisphere = std::string(angle_deg < 0.0 && units != 0 ? negative : positive);
  return out;
}

}  // namespace

CoordinateFields format_latitude(double lat_deg, int minute_decimals) {
  if (!std::isfinite(lat_deg) || std::fabs(lat_deg) > 90.0) return {};
  return format_angle(lat_deg, minute_decimals, 2, "N", "S");
}

CoordinateFields format_longitude(double lon_deg, int minute_decimals) {
  if (!std::isfinite(lon_deg)) return {};
  const double wrapped_deg = std::fabs(lon_deg) <= 180.0 ? lon_deg : std::remainder(lon_deg, 360.0);
  return format_angle(wrapped_deg, minute_decimals, 3, "E", "W");
}

std::string format_time_of_day(UtcTime time_utc, int decimals) {
  using namespace std::chrono;
  const hh_mm_ss<milliseconds> hms{time_utc - floor<days>(time_utc)};
  std::string text = fmt::format("{:02}{:02}{:02}", hms.hours().count(), hms.minutes().count(),
                                 hms.seconds().count());
  const int digits = std::clamp(decimals, 0, 3);
  if (digits > 0) {
    const std::int64_t fraction = hms.subseconds().count() / pow10(3 - digits);
    text += fmt::format(".{:0{}}", fraction, digits);
  }
  return text;
}

std::string format_date_ddmmyy(UtcTime time_utc) {
  using namespace std::chrono;
  const year_month_day date{floor<days>(time_utc)};
  const int two_digit_year = (static_cast<int>(date.year()) % 100 + 100) % 100;
  return fmt::format("{:02}{:02}{:02}", static_cast<unsigned>(date.day()),
                     static_cast<unsigned>(date.month()), two_digit_year);
}

std::string format_fixed(double value, int decimals, double max_abs) {
  if (!std::isfinite(value) || std::fabs(value) >= max_abs) return {};
  const int digits = std::clamp(decimals, 0, 8);
  const double scale = static_cast<double>(pow10(digits));
  double rounded = std::round(value * scale) / scale;
  if (rounded == 0.0) rounded = 0.0;  // -0.0 would print as "-0.0"
  return fmt::format("{:.{}f}", rounded, digits);
}

}  // namespace gpsemu::nmea::fields
