// GGA, RMC, VTG and GLL formatters: written straight into the output buffer from the epoch's
// shared fields (epoch_fields.hpp), framed with the checksum by text::put_checksum.
// (ZDA, GST: sentences_more.cpp; GSA, GSV: satellites.cpp; the epoch: epoch.cpp.)
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "nmea/epoch_fields.hpp"
#include "nmea/fields.hpp"
#include "nmea/sentences.hpp"
#include "nmea/text_append.hpp"

namespace gpsemu::nmea {
namespace {

// Largest magnitudes that still fit their field; beyond them the field is left empty.
constexpr double max_alt_m = 1e6;
constexpr double max_geoid_sep_m = 1e4;
constexpr double max_speed_knots = 1e6;
constexpr double kmh_per_mps = 3.6;

// Most bytes put_gga or put_rmc writes besides the talker (GGA: at most 122, with 8 decimals of
// minutes, 3 of seconds, a 20-digit quality, "-1000000.0000" altitudes and "999.9,4095" of
// differential data; RMC fewer), plus the 16 bytes put_field may copy past the end of a field.
constexpr std::size_t max_sentence_bytes = 126 + 16;

// Writes ",value,unit" ("545.4,M") of a value with `decimals` decimals; two empty fields when the
// value is left empty (a 2-D fix, or it does not fit below max_abs).
char* put_with_unit(char* p, bool leave_empty, double value, double max_abs, char unit, int decimals = 1) {
  *p++ = ',';
  char* const value_start = p;
  if (!leave_empty) p = fields::put_fixed(p, value, decimals, max_abs);
  const bool written = p != value_start;
  *p++ = ',';
  if (written) *p++ = unit;
  return p;
}

// "$" + talker + type: the start of every sentence (the body ends with text::put_checksum).
char* put_start(char* p, const FormatOptions& options, std::string_view type) {
  *p++ = '$';
  for (const char c : options.talker) *p++ = c;
  return text::put_chars(p, type);
}

// Appends the sentence `write(begin)` writes into `out`, sized for max_sentence_bytes + talker.
template <typename Write>
void append_sentence(std::string& out, const FormatOptions& options, Write write) {
  const std::size_t start = out.size();
  out.resize(start + max_sentence_bytes + options.talker.size());
  char* const end = write(out.data() + start);
  out.resize(static_cast<std::size_t>(end - out.data()));
}

char* put_gga(char* const begin, const Fix& fix, const FormatOptions& options, const EpochFields& fields) {
  char* p = put_start(begin, options, "GGA,");
  p = put_field(p, fields.time);
  if (!fix.has_fix()) {
    p = text::put_chars(p, ",,,,,0,00,99.99,,,,,,");
    return text::put_checksum(begin, p);
  }
  const int satellites = std::clamp(fix.satellites_used, 0, 99);
  const double hdop = std::clamp(fix.hdop, 0.0, 99.99);
  const bool two_d = fix.dimension == FixDimension::two_d;  // no altitude in a 2-D fix
  *p++ = ',';
  p = put_field(p, fields.latitude);
  *p++ = ',';
  p = put_field(p, fields.longitude);
  *p++ = ',';
  p = text::put_uint(p, static_cast<std::uint64_t>(static_cast<int>(fix.quality)));
  *p++ = ',';
  p = text::put_uint(p, static_cast<std::uint64_t>(satellites), 2);
  *p++ = ',';
  p = fields::put_fixed(p, hdop, 2, 100.0);
  p = put_with_unit(p, two_d, fix.alt_msl_m, max_alt_m, 'M', std::clamp(options.alt_decimals, 0, 4));
  p = put_with_unit(p, two_d, fix.geoid_sep_m, max_geoid_sep_m, 'M');
  *p++ = ',';  // age of differential data (seconds) and reference station, as a u-blox writes them
  if (fix.diff_age_s) p = fields::put_fixed(p, std::clamp(*fix.diff_age_s, 0.0, 999.9), 1, 1000.0);
  *p++ = ',';
  if (fix.diff_station_id) p = text::put_uint(p, static_cast<std::uint64_t>(std::clamp(*fix.diff_station_id, 0, 4095)), 4);
  return text::put_checksum(begin, p);
}

char* put_rmc(char* const begin, const Fix& fix, const FormatOptions& options, const EpochFields& fields) {
  const std::string_view nav_status = options.version == NmeaVersion::v4_1 ? ",V" : "";
  char* p = put_start(begin, options, "RMC,");
  p = put_field(p, fields.time);
  if (!fix.has_fix()) {
    p = text::put_chars(p, ",V,,,,,,,");
    p = put_field(p, fields.date);
    p = text::put_chars(p, ",,,N");
    p = text::put_chars(p, nav_status);
    return text::put_checksum(begin, p);
  }
  const double speed_knots = std::fabs(fix.speed_mps) * fields::knots_per_mps;
  p = text::put_chars(p, ",A,");
  p = put_field(p, fields.latitude);
  *p++ = ',';
  p = put_field(p, fields.longitude);
  *p++ = ',';
  p = fields::put_fixed(p, speed_knots, 3, max_speed_knots);
  *p++ = ',';
  p = fields::put_course(p, fix.course_deg_true);
  *p++ = ',';
  p = put_field(p, fields.date);
  p = text::put_chars(p, ",,,");
  *p++ = mode_indicator(fix.quality);
  p = text::put_chars(p, nav_status);
  return text::put_checksum(begin, p);
}

char* put_vtg(char* const begin, const Fix& fix, const FormatOptions& options) {
  char* p = put_start(begin, options, "VTG,");
  if (!fix.has_fix()) {
    p = text::put_chars(p, ",T,,M,,N,,K,N");
    return text::put_checksum(begin, p);
  }
  const double speed_mps = std::fabs(fix.speed_mps);
  p = fields::put_course(p, fix.course_deg_true);
  p = text::put_chars(p, ",T,,M,");
  p = fields::put_fixed(p, speed_mps * fields::knots_per_mps, 3, max_speed_knots);
  p = text::put_chars(p, ",N,");
  p = fields::put_fixed(p, speed_mps * kmh_per_mps, 3, max_speed_knots * 2);
  p = text::put_chars(p, ",K,");
  *p++ = mode_indicator(fix.quality);
  return text::put_checksum(begin, p);
}

char* put_gll(char* const begin, const Fix& fix, const FormatOptions& options, const EpochFields& fields) {
  char* p = put_start(begin, options, "GLL,");
  if (!fix.has_fix()) {
    p = text::put_chars(p, ",,,,");
    p = put_field(p, fields.time);
    p = text::put_chars(p, ",V,N");
    return text::put_checksum(begin, p);
  }
  p = put_field(p, fields.latitude);
  *p++ = ',';
  p = put_field(p, fields.longitude);
  *p++ = ',';
  p = put_field(p, fields.time);
  p = text::put_chars(p, ",A,");
  *p++ = mode_indicator(fix.quality);
  return text::put_checksum(begin, p);
}

template <typename Put>
void set_field(FieldText& field, Put put) {
  field.size = static_cast<std::uint8_t>(put(field.chars.data()) - field.chars.data());
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

EpochFields epoch_fields(const Fix& fix, const FormatOptions& options, bool with_date) {
  EpochFields out;
  if (!fix.time_valid) return out;  // no time, so no date and no position either
  set_field(out.time, [&](char* p) {
    return fields::put_time_of_day(p, fix.time_utc, options.time_decimals, fix.leap.in_second_60);
  });
  if (with_date) set_field(out.date, [&](char* p) { return fields::put_date_ddmmyy(p, fix.time_utc); });
  if (fix.has_fix()) {
    set_field(out.latitude, [&](char* p) { return fields::put_latitude(p, fix.lat_deg, options.minute_decimals); });
    set_field(out.longitude,
              [&](char* p) { return fields::put_longitude(p, fix.lon_deg, options.minute_decimals); });
  }
  return out;
}

void append_gga(const Fix& fix, const FormatOptions& options, const EpochFields& fields, std::string& out) {
  append_sentence(out, options, [&](char* p) { return put_gga(p, fix, options, fields); });
}

void append_rmc(const Fix& fix, const FormatOptions& options, const EpochFields& fields, std::string& out) {
  append_sentence(out, options, [&](char* p) { return put_rmc(p, fix, options, fields); });
}

void append_vtg(const Fix& fix, const FormatOptions& options, std::string& out) {
  append_sentence(out, options, [&](char* p) { return put_vtg(p, fix, options); });
}

void append_gll(const Fix& fix, const FormatOptions& options, const EpochFields& fields, std::string& out) {
  append_sentence(out, options, [&](char* p) { return put_gll(p, fix, options, fields); });
}

std::string format_vtg(const Fix& fix, const FormatOptions& options) {
  std::string out;
  append_vtg(fix, options, out);
  return out;
}

std::string format_gll(const Fix& fix, const FormatOptions& options) {
  std::string out;
  append_gll(fix, options, epoch_fields(fix, options, false), out);
  return out;
}

std::string format_gga(const Fix& fix, const FormatOptions& options) {
  std::string out;
  append_gga(fix, options, epoch_fields(fix, options, false), out);
  return out;
}

std::string format_rmc(const Fix& fix, const FormatOptions& options) {
  std::string out;
  append_rmc(fix, options, epoch_fields(fix, options, true), out);
  return out;
}

}  // namespace gpsemu::nmea
