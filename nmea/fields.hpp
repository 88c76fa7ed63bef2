// Field-level building blocks of the NMEA formatters: latitude/longitude as ddmm.mmmmm plus
// hemisphere, hhmmss.ss times, ddmmyy dates and fixed-decimal numbers. Internal to nmea/ (the
// sentence formatters in sentences.cpp are the public interface). Pure functions.
//
// Each field comes twice: format_* returns a std::string; put_* writes the same characters at `p`
// into a buffer the caller has sized (the per-epoch GGA/RMC path, which allocates nothing) and
// returns the end of what it wrote.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "nmea/fix.hpp"
#include "nmea/text_append.hpp"

namespace gpsemu::nmea::fields {

/// A latitude or a longitude as its two NMEA fields.
struct CoordinateFields {
  std::string value;       ///< "ddmm.mmmmm" (latitude) or "dddmm.mmmmm" (longitude), zero padded
  std::string hemisphere;  ///< "N"/"S" or "E"/"W"; empty exactly when `value` is empty
};

/// Latitude in degrees (north positive, [-90, 90]) rounded to `minute_decimals` (clamped to 1..8)
/// decimals of minutes first, then split into degrees and minutes with integer arithmetic, so
/// 47.99999999 prints "4800.00000", never "4760.00000". Zero (and anything that rounds to zero)
/// is "N". Non-finite or |lat| > 90 gives empty fields.
[[nodiscard]] CoordinateFields format_latitude(double lat_deg, int minute_decimals);

/// Longitude in degrees (east positive), first brought into [-180, 180] (190 is -170), then
/// formatted like format_latitude with three degree digits; 0 is "E", 179.99999999 rounds to
/// "18000.00000","E" at 5 decimals (-180 is "18000.00000","W"). Non-finite input gives empty fields.
[[nodiscard]] CoordinateFields format_longitude(double lon_deg, int minute_decimals);

/// UTC time of day "hhmmss", plus "." and `decimals` (clamped to 0..3) digits of the second when
/// `decimals` > 0. Digits are truncated from the milliseconds, never rounded: 23:59:59.999 with two
/// decimals is "235959.99". `second_60`: inside an inserted leap second, `time_utc` the second
/// before it: 23:59:59.5 is written "235960.50".
[[nodiscard]] std::string format_time_of_day(UtcTime time_utc, int decimals, bool second_60 = false);

/// UTC date "ddmmyy" (two-digit year).
[[nodiscard]] std::string format_date_ddmmyy(UtcTime time_utc);

/// `value` rounded half away from zero to `decimals` (0..8) decimals, fixed notation, never
/// "-0.0". Empty when `value` is not finite or |value| >= `max_abs` (a field that would not fit).
[[nodiscard]] std::string format_fixed(double value, int decimals, double max_abs = 1e9);

/// Most characters put_latitude or put_longitude writes ("18000.00000000,W").
inline constexpr std::size_t max_coordinate_chars = 16;

/// Writes format_latitude's value and hemisphere joined by a comma ("4717.11399,N"); "," when empty.
char* put_latitude(char* p, double lat_deg, int minute_decimals);
/// Writes format_longitude's value and hemisphere joined by a comma ("00833.91590,E"); "," when empty.
char* put_longitude(char* p, double lon_deg, int minute_decimals);
/// Writes format_time_of_day(time_utc, decimals, second_60): at most 10 characters.
char* put_time_of_day(char* p, UtcTime time_utc, int decimals, bool second_60 = false);
/// Writes format_date_ddmmyy(time_utc): 6 characters.
char* put_date_ddmmyy(char* p, UtcTime time_utc);
/// Writes `value` (finite) rounded half away from zero to `digits` (0..8) decimals, as
/// format_fixed, when that is fewer than 10^15 units of the last digit (at most 17 characters),
/// and returns the end; nullptr, nothing written, beyond. Below 10^15 units the double nearest
/// units/10^digits prints (correctly rounded to `digits` decimals) as exactly those units: its
/// error, under 0.12 of the last digit, cannot round away; so writing the units with integers gives
/// byte for byte what fmt writes, without its cost. Inline, so constant digits make the scaling and
/// the split constant arithmetic.
inline char* put_fixed_units(char* p, double value, int digits) {
  const double units = value * static_cast<double>(text::pow10(digits));
  if (!(std::fabs(units) < 1e15)) return nullptr;
  const std::int64_t rounded = text::round_half_away(units);  // as std::round; -0 becomes 0
  if (rounded <= -1'000'000'000'000'000 || rounded >= 1'000'000'000'000'000) return nullptr;
  return text::put_scaled(p, rounded, digits);
}

/// format_fixed's general case (10^15 units of the last digit or more), with fmt.
[[nodiscard]] std::string format_fixed_with_fmt(double value, int digits);

/// Writes format_fixed(value, decimals, max_abs): at most 17 characters when
/// max_abs x 10^decimals <= 10^15 (the caller's buffer must hold what format_fixed would return).
inline char* put_fixed(char* p, double value, int decimals, double max_abs) {
  if (!std::isfinite(value) || std::fabs(value) >= max_abs) return p;
  const int digits = std::clamp(decimals, 0, 8);
  if (char* const end = put_fixed_units(p, value, digits)) return end;
  return text::put_chars(p, format_fixed_with_fmt(value, digits));
}

/// Writes format_course(course_deg_true): at most 6 characters.
char* put_course(char* p, const std::optional<double>& course_deg_true);

/// Knots per metre per second (1 kn = 1852 m / 3600 s).
inline constexpr double knots_per_mps = 3600.0 / 1852.0;

/// Course over ground "c.cc" in degrees true, normalised into [0, 360) after rounding (359.999 is
/// "0.00"); empty when unknown or not finite. (RMC, VTG.)
[[nodiscard]] std::string format_course(const std::optional<double>& course_deg_true);

}  // namespace gpsemu::nmea::fields
