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

constexpr std::int64_t pow10(int exponent) { return static_cast<std::int64_t>(text::pow10(exponent)); }

struct PutAngle {
  char* end;      // the end of what was written
  bool negative;  // the angle is below zero and does not round to zero
};

// Writes |angle_deg| as degrees (`degree_digits` digits), minutes and `Decimals` decimals:
// rounded once in units of 10^-Decimals minutes, then split with integers (constant divisors).
template <int Decimals>
PutAngle put_angle(char* p, double angle_deg, int degree_digits) {
  constexpr std::int64_t units_per_minute = pow10(Decimals);
  constexpr std::int64_t units_per_degree = 60 * units_per_minute;
  // |angle| <= 180 and decimals <= 8: at most 1.08e12 units, exact in a double and an int64.
  const std::int64_t units = text::round_half_away(std::fabs(angle_deg) * static_cast<double>(units_per_degree));
  const std::int64_t degrees = units / units_per_degree;
  const std::int64_t minute_units = units % units_per_degree;
  p = text::put_digits(p, static_cast<std::uint64_t>(degrees), degree_digits);
  p = text::put_digits(p, static_cast<std::uint64_t>(minute_units / units_per_minute), 2);
  *p++ = '.';
  p = text::put_digits(p, static_cast<std::uint64_t>(minute_units % units_per_minute), Decimals);
  return {p, angle_deg < 0.0 && units != 0};
}

// put_angle with `minute_decimals` clamped to 1..8.
PutAngle put_angle(char* p, double angle_deg, int minute_decimals, int degree_digits) {
  switch (std::clamp(minute_decimals, 1, 8)) {
    case 1: return put_angle<1>(p, angle_deg, degree_digits);
    case 2: return put_angle<2>(p, angle_deg, degree_digits);
    case 3: return put_angle<3>(p, angle_deg, degree_digits);
    case 4: return put_angle<4>(p, angle_deg, degree_digits);
    case 5: return put_angle<5>(p, angle_deg, degree_digits);
    case 6: return put_angle<6>(p, angle_deg, degree_digits);
    case 7: return put_angle<7>(p, angle_deg, degree_digits);
    default: return put_angle<8>(p, angle_deg, degree_digits);
  }
}

bool latitude_in_range(double lat_deg) { return std::isfinite(lat_deg) && std::fabs(lat_deg) <= 90.0; }

// Longitude brought into [-180, 180] (190 is -170).
double wrap_longitude(double lon_deg) {
  return std::fabs(lon_deg) <= 180.0 ? lon_deg : std::remainder(lon_deg, 360.0);
}

CoordinateFields format_angle(double angle_deg, int minute_decimals, int degree_digits, char positive,
                              char negative) {
  char text[max_coordinate_chars];
  const PutAngle angle = put_angle(text, angle_deg, minute_decimals, degree_digits);
  return {std::string(text, angle.end), std::string(1, angle.negative ? negative : positive)};
}

char* put_coordinate(char* p, double angle_deg, int minute_decimals, int degree_digits, char positive,
                     char negative) {
  const PutAngle angle = put_angle(p, angle_deg, minute_decimals, degree_digits);
  p = angle.end;
  *p++ = ',';
  *p++ = angle.negative ? negative : positive;
  return p;
}

}  // namespace

CoordinateFields format_latitude(double lat_deg, int minute_decimals) {
  if (!latitude_in_range(lat_deg)) return {};
  return format_angle(lat_deg, minute_decimals, 2, 'N', 'S');
}

CoordinateFields format_longitude(double lon_deg, int minute_decimals) {
  if (!std::isfinite(lon_deg)) return {};
  return format_angle(wrap_longitude(lon_deg), minute_decimals, 3, 'E', 'W');
}

char* put_latitude(char* p, double lat_deg, int minute_decimals) {
  if (!latitude_in_range(lat_deg)) {
    *p++ = ',';
    return p;
  }
  return put_coordinate(p, lat_deg, minute_decimals, 2, 'N', 'S');
}

char* put_longitude(char* p, double lon_deg, int minute_decimals) {
  if (!std::isfinite(lon_deg)) {
    *p++ = ',';
    return p;
  }
  return put_coordinate(p, wrap_longitude(lon_deg), minute_decimals, 3, 'E', 'W');
}

char* put_time_of_day(char* p, UtcTime time_utc, int decimals, bool second_60) {
  constexpr std::int64_t ms_per_day = 86'400'000;
  std::int64_t ms = time_utc.time_since_epoch().count() % ms_per_day;  // of the day
  if (ms < 0) ms += ms_per_day;
  p = text::put_digits(p, static_cast<std::uint64_t>(ms / 3'600'000), 2);
  p = text::put_digits(p, static_cast<std::uint64_t>(ms / 60'000 % 60), 2);
  p = text::put_digits(p, static_cast<std::uint64_t>(ms / 1000 % 60 + (second_60 ? 1 : 0)), 2);
  const int digits = std::clamp(decimals, 0, 3);
  if (digits > 0) {
    *p++ = '.';
    p = text::put_digits(p, static_cast<std::uint64_t>(ms % 1000 / pow10(3 - digits)), digits);
  }
  return p;
}

std::string format_time_of_day(UtcTime time_utc, int decimals, bool second_60) {
  char text[16];
  return std::string(text, put_time_of_day(text, time_utc, decimals, second_60));
}

char* put_date_ddmmyy(char* p, UtcTime time_utc) {
  using namespace std::chrono;
  const year_month_day date{floor<days>(time_utc)};
  const int two_digit_year = (static_cast<int>(date.year()) % 100 + 100) % 100;
  p = text::put_digits(p, static_cast<unsigned>(date.day()), 2);
  p = text::put_digits(p, static_cast<unsigned>(date.month()), 2);
  return text::put_digits(p, static_cast<std::uint64_t>(two_digit_year), 2);
}

std::string format_date_ddmmyy(UtcTime time_utc) {
  char text[8];
  return std::string(text, put_date_ddmmyy(text, time_utc));
}

std::string format_fixed_with_fmt(double value, int digits) {
  // The same rounding half away from zero as put_fixed_units, then fmt.
  const double scale = static_cast<double>(pow10(digits));
  double rounded = std::round(value * scale) / scale;
  if (rounded == 0.0) rounded = 0.0;  // -0.0 would print as "-0.0"
  return fmt::format("{:.{}f}", rounded, digits);
}

std::string format_fixed(double value, int decimals, double max_abs) {
  if (!std::isfinite(value) || std::fabs(value) >= max_abs) return {};
  const int digits = std::clamp(decimals, 0, 8);
  char text[24];
  if (char* const end = put_fixed_units(text, value, digits)) return std::string(text, end);
  return format_fixed_with_fmt(value, digits);
}

char* put_course(char* p, const std::optional<double>& course_deg_true) {
  if (!course_deg_true || !std::isfinite(*course_deg_true)) return p;
  // fmod returns a value already in (-360, 360) unchanged: skip the call then.
  const double course_deg = *course_deg_true;
  const double normalised_deg = std::fabs(course_deg) < 360.0 ? course_deg : std::fmod(course_deg, 360.0);
  std::int64_t centidegrees = text::round_half_away(normalised_deg * 100.0) % 36000;
  if (centidegrees < 0) centidegrees += 36000;
  return text::put_scaled(p, centidegrees, 2);
}

std::string format_course(const std::optional<double>& course_deg_true) {
  char text[16];
  return std::string(text, put_course(text, course_deg_true));
}

}  // namespace gpsemu::nmea::fields
