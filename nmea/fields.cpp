#include "nmea/fields.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string_view>

#include "nmea/text_append.hpp"

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
  text::append_uint(out.value, static_cast<std::uint64_t>(degrees), degree_digits);
  text::append_uint(out.value, static_cast<std::uint64_t>(minute_units / units_per_minute), 2);
  out.value += '.';
  text::append_uint(out.value, static_cast<std::uint64_t>(minute_units % units_per_minute), decimals);
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
  std::string out;
  text::append_uint(out, static_cast<std::uint64_t>(hms.hours().count()), 2);
  text::append_uint(out, static_cast<std::uint64_t>(hms.minutes().count()), 2);
  text::append_uint(out, static_cast<std::uint64_t>(hms.seconds().count()), 2);
  const int digits = std::clamp(decimals, 0, 3);
  if (digits > 0) {
    const std::int64_t fraction = hms.subseconds().count() / pow10(3 - digits);
    out += '.';
    text::append_uint(out, static_cast<std::uint64_t>(fraction), digits);
  }
  return out;
}

std::string format_date_ddmmyy(UtcTime time_utc) {
  using namespace std::chrono;
  const year_month_day date{floor<days>(time_utc)};
  const int two_digit_year = (static_cast<int>(date.year()) % 100 + 100) % 100;
  std::string out;
  text::append_uint(out, static_cast<unsigned>(date.day()), 2);
  text::append_uint(out, static_cast<unsigned>(date.month()), 2);
  text::append_uint(out, static_cast<std::uint64_t>(two_digit_year), 2);
  return out;
}

std::string format_fixed(double value, int decimals, double max_abs) {
  if (!std::isfinite(value) || std::fabs(value) >= max_abs) return {};
  const int digits = std::clamp(decimals, 0, 8);
  const double scale = static_cast<double>(pow10(digits));
  const double units = std::round(value * scale);
  double rounded = units / scale;
  if (rounded == 0.0) rounded = 0.0;  // -0.0 would print as "-0.0"
  // Below 10^15 units, the double nearest units/10^digits prints (correctly rounded to `digits`
  // decimals) as exactly those units: its error, under 0.12 of the last digit, cannot round away.
  // Written with integers then, byte for byte what fmt writes, without its cost.
  if (std::fabs(units) < 1e15) {
    std::string out;
    text::append_scaled(out, rounded == 0.0 ? 0 : static_cast<std::int64_t>(units), digits);
    return out;
  }
  return fmt::format("{:.{}f}", rounded, digits);
}

std::string format_course(const std::optional<double>& course_deg_true) {
  if (!course_deg_true || !std::isfinite(*course_deg_true)) return {};
  const double normalised_deg = std::fmod(*course_deg_true, 360.0);
  std::int64_t centidegrees = std::llround(normalised_deg * 100.0) % 36000;
  if (centidegrees < 0) centidegrees += 36000;
  std::string out;
  text::append_scaled(out, centidegrees, 2);
  return out;
}

}  // namespace gpsemu::nmea::fields
