// Sentence framing/checksum and the GGA and RMC parsers. Numbers are read with std::from_chars
// after checking their characters, so nothing here throws on bad input.
#include "nmea/parse.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <system_error>

#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {

using std::chrono::milliseconds;

constexpr double mps_per_knot = 1852.0 / 3600.0;

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_printable(char c) { return c >= 0x20 && c <= 0x7E; }

std::optional<int> hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return std::nullopt;
}

// Digits with at most one '.', at least one digit, and a leading '-' when `allow_sign`.
std::optional<double> to_decimal(std::string_view s, bool allow_sign) {
  std::string_view digits = s;
  if (allow_sign && !digits.empty() && digits.front() == '-') digits.remove_prefix(1);
  if (std::count(digits.begin(), digits.end(), '.') > 1) return std::nullopt;
  if (std::count_if(digits.begin(), digits.end(), is_digit) == 0) return std::nullopt;
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return is_digit(c) || c == '.'; })) {
    return std::nullopt;
  }
  double value = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value, std::chars_format::fixed);
  if (ec != std::errc{} || end != s.data() + s.size()) return std::nullopt;
  return value;
}

std::optional<int> to_int(std::string_view s) {
  if (s.empty() || !all_digits(s)) return std::nullopt;
  int value = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc{} || end != s.data() + s.size()) return std::nullopt;
  return value;
}

struct Coordinate {
  std::optional<double> deg;
  int minute_decimals = 0;
};

// Reads the fields of one sentence by index. A missing trailing field reads as empty; the first
// malformed field marks the whole reader failed (the sentence is then rejected).
class FieldReader {
 public:
  explicit FieldReader(const std::vector<std::string>& fields) : fields_(fields) {}

  [[nodiscard]] bool failed() const { return failed_; }
  [[nodiscard]] std::string_view text(std::size_t i) const {
    return i < fields_.size() ? std::string_view{fields_[i]} : std::string_view{};
  }

  std::optional<double> decimal(std::size_t i, bool allow_sign = false) {
    if (text(i).empty()) return std::nullopt;
    return check(to_decimal(text(i), allow_sign));
  }

  std::optional<int> integer(std::size_t i) {
    if (text(i).empty()) return std::nullopt;
    return check(to_int(text(i)));
  }

  // One upper-case letter, or nothing.
  std::optional<char> letter(std::size_t i) {
    const std::string_view s = text(i);
    if (s.empty()) return std::nullopt;
    return check(s.size() == 1 && s[0] >= 'A' && s[0] <= 'Z' ? std::optional<char>{s[0]} : std::nullopt);
  }

  // Empty, or exactly `expected` (e.g. the "M" after an altitude).
  void expect_empty_or(std::size_t i, std::string_view expected) {
    if (!text(i).empty() && text(i) != expected) failed_ = true;
  }

  // "hhmmss" with an optional fraction of any length, truncated to milliseconds. ss may be 60
  // (leap second).
  std::optional<milliseconds> time_of_day(std::size_t i) {
    const std::string_view s = text(i);
    if (s.empty()) return std::nullopt;
    const std::string_view fraction = s.size() > 6 && s[6] == '.' ? s.substr(7) : std::string_view{};
    if (s.size() < 6 || !all_digits(s.substr(0, 6)) || !all_digits(fraction) ||
        (s.size() > 6 && s[6] != '.')) {
      return check<milliseconds>(std::nullopt);
    }
    const int hours = (s[0] - '0') * 10 + (s[1] - '0');
    const int minutes = (s[2] - '0') * 10 + (s[3] - '0');
    const int seconds = (s[4] - '0') * 10 + (s[5] - '0');
    if (hours > 23 || minutes > 59 || seconds > 60) return check<milliseconds>(std::nullopt);
    int millis = 0;
    for (std::size_t k = 0; k < 3; ++k) millis = millis * 10 + (k < fraction.size() ? fraction[k] - '0' : 0);
    return milliseconds{((hours * 60 + minutes) * 60 + seconds) * 1000 + millis};
  }

  // "ddmmyy"; yy < 80 is 20yy, otherwise 19yy.
  std::optional<std::chrono::year_month_day> date(std::size_t i) {
    const std::string_view s = text(i);
    if (s.empty()) return std::nullopt;
    if (s.size() != 6 || !all_digits(s)) return check<std::chrono::year_month_day>(std::nullopt);
    const int day = (s[0] - '0') * 10 + (s[1] - '0');
    const int month = (s[2] - '0') * 10 + (s[3] - '0');
    const int yy = (s[4] - '0') * 10 + (s[5] - '0');
    const std::chrono::year_month_day ymd{std::chrono::year{yy < 80 ? 2000 + yy : 1900 + yy},
                                          std::chrono::month{static_cast<unsigned>(month)},
                                          std::chrono::day{static_cast<unsigned>(day)}};
    return check(ymd.ok() ? std::optional{ymd} : std::nullopt);
  }

  // "ddmm.mmmm" / "dddmm.mmmm" and its hemisphere field. Leading degree digits are not counted
  // (2 to 5 digits before the '.'); minutes must be < 60 and the angle within `max_deg`.
  Coordinate coordinate(std::size_t value_i, std::size_t hemisphere_i, char positive, char negative,
                        double max_deg) {
    const std::string_view s = text(value_i);
    const std::string_view hemisphere = text(hemisphere_i);
    if (s.empty()) return {};
    const std::size_t dot = s.find('.');
    const std::size_t int_digits = dot == std::string_view::npos ? s.size() : dot;
    const bool hemisphere_ok = hemisphere.size() == 1 && (hemisphere[0] == positive || hemisphere[0] == negative);
    if (int_digits < 2 || int_digits > 5 || !hemisphere_ok) {
      failed_ = true;
      return {};
    }
    // Degrees and minutes read apart: "17959.99999999" keeps every digit of its minutes.
    const std::string_view degree_text = s.substr(0, int_digits - 2);
    const std::optional<int> degrees = degree_text.empty() ? std::optional{0} : to_int(degree_text);
    const std::optional<double> minutes = to_decimal(s.substr(int_digits - 2), false);
    if (!degrees || !minutes || *minutes >= 60.0 || *degrees + *minutes / 60.0 > max_deg) {
      failed_ = true;
      return {};
    }
    const double angle_deg = *degrees + *minutes / 60.0;
    const int decimals = dot == std::string_view::npos ? 0 : static_cast<int>(s.size() - dot - 1);
    return {hemisphere[0] == negative ? -angle_deg : angle_deg, decimals};
  }

 private:
  template <class T>
  std::optional<T> check(std::optional<T> value) {
    if (!value) failed_ = true;
    return value;
  }

  const std::vector<std::string>& fields_;
  bool failed_ = false;
};

}  // namespace

bool all_digits(std::string_view text) { return std::all_of(text.begin(), text.end(), is_digit); }

std::string_view to_string(ParseError error) {
  switch (error) {
    case ParseError::missing_dollar: return "missing_dollar";
    case ParseError::too_long: return "too_long";
    case ParseError::bad_character: return "bad_character";
    case ParseError::missing_checksum: return "missing_checksum";
    case ParseError::malformed_checksum: return "malformed_checksum";
    case ParseError::bad_checksum: return "bad_checksum";
    case ParseError::bad_address: return "bad_address";
    case ParseError::wrong_type: return "wrong_type";
    case ParseError::too_few_fields: return "too_few_fields";
    case ParseError::malformed_field: return "malformed_field";
  }
  return "unknown";
}

Result<Sentence> parse_sentence(std::string_view line) {
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.remove_suffix(1);
  if (line.empty() || line.front() != '$') return ParseError::missing_dollar;
  if (line.size() > max_parse_chars) return ParseError::too_long;
  const std::string_view after_dollar = line.substr(1);
  if (!std::all_of(after_dollar.begin(), after_dollar.end(), [](char c) { return is_printable(c) && c != '$'; })) {
    return ParseError::bad_character;
  }
  const std::size_t star = after_dollar.find('*');
  if (star == std::string_view::npos) return ParseError::missing_checksum;
  const std::string_view hex = after_dollar.substr(star + 1);
  if (hex.size() != 2 || !hex_digit(hex[0]) || !hex_digit(hex[1])) return ParseError::malformed_checksum;
  const std::string_view body = after_dollar.substr(0, star);
  if (checksum(body) != *hex_digit(hex[0]) * 16 + *hex_digit(hex[1])) return ParseError::bad_checksum;

  const std::size_t comma = body.find(',');
  const std::string_view address = body.substr(0, comma);
  const bool address_ok = address.size() >= 3 && std::all_of(address.begin(), address.end(), [](char c) {
    return is_digit(c) || (c >= 'A' && c <= 'Z');
  });
  if (!address_ok) return ParseError::bad_address;
  const std::size_t talker_chars = address.front() == 'P' ? 1 : 2;
  Sentence sentence{std::string(address.substr(0, talker_chars)), std::string(address.substr(talker_chars)), {}};
  std::string_view rest = comma == std::string_view::npos ? std::string_view{} : body.substr(comma);
  while (!rest.empty()) {  // rest is "," field [, field ...]
    rest.remove_prefix(1);
    const std::size_t next = rest.find(',');
    sentence.fields.emplace_back(rest.substr(0, next));
    rest = next == std::string_view::npos ? std::string_view{} : rest.substr(next);
  }
  return sentence;
}

Result<GgaData> parse_gga(const Sentence& sentence) {
  if (sentence.type != "GGA") return ParseError::wrong_type;
  if (sentence.fields.size() < 12) return ParseError::too_few_fields;
  FieldReader in(sentence.fields);
  GgaData gga;
  gga.time_of_day = in.time_of_day(0);
  const Coordinate lat = in.coordinate(1, 2, 'N', 'S', 90.0);
  const Coordinate lon = in.coordinate(3, 4, 'E', 'W', 180.0);
  gga.lat_deg = lat.deg;
  gga.lon_deg = lon.deg;
  gga.minute_decimals = lat.minute_decimals;
  const std::optional<int> quality = in.integer(5);
  if (quality && *quality > static_cast<int>(FixQuality::estimated)) return ParseError::malformed_field;
  gga.quality = static_cast<FixQuality>(quality.value_or(0));
  gga.satellites = in.integer(6);
  gga.hdop = in.decimal(7);
  gga.alt_msl_m = in.decimal(8, true);
  in.expect_empty_or(9, "M");
  gga.geoid_sep_m = in.decimal(10, true);
  in.expect_empty_or(11, "M");
  if (in.failed()) return ParseError::malformed_field;
  return gga;
}

Result<RmcData> parse_rmc(const Sentence& sentence) {
  if (sentence.type != "RMC") return ParseError::wrong_type;
  if (sentence.fields.size() < 11) return ParseError::too_few_fields;
  FieldReader in(sentence.fields);
  RmcData rmc;
  rmc.time_of_day = in.time_of_day(0);
  const std::optional<char> status = in.letter(1);
  if (status && *status != 'A' && *status != 'V') return ParseError::malformed_field;
  rmc.status_active = status == 'A';
  const Coordinate lat = in.coordinate(2, 3, 'N', 'S', 90.0);
  const Coordinate lon = in.coordinate(4, 5, 'E', 'W', 180.0);
  rmc.lat_deg = lat.deg;
  rmc.lon_deg = lon.deg;
  rmc.minute_decimals = lat.minute_decimals;
  if (const std::optional<double> knots = in.decimal(6)) rmc.speed_mps = *knots * mps_per_knot;
  rmc.course_deg_true = in.decimal(7);
  rmc.date = in.date(8);
  const std::optional<double> variation_deg = in.decimal(9);
  const std::optional<char> variation_dir = in.letter(10);
  if (variation_deg) {
    if (variation_dir != 'E' && variation_dir != 'W') return ParseError::malformed_field;
    rmc.magnetic_variation_deg = variation_dir == 'W' ? -*variation_deg : *variation_deg;
  }
  rmc.mode = in.letter(11);
  rmc.nav_status = in.letter(12);
  if (in.failed()) return ParseError::malformed_field;
  return rmc;
}

std::optional<UtcTime> utc_time(const RmcData& rmc) {
  if (!rmc.date || !rmc.time_of_day) return std::nullopt;
  return UtcTime{std::chrono::sys_days{*rmc.date}.time_since_epoch()} + *rmc.time_of_day;
}

}  // namespace gpsemu::nmea
