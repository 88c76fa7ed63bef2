// Parsing NMEA 0183 text back into values (tests, log replay, calibration): the framing and
// checksum of one sentence, one function per sentence type (GGA, RMC), and an incremental reader
// for a real receiver's byte stream. Pure: no I/O, and bad input is a ParseError value, never an
// exception or a crash.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "nmea/fix.hpp"

namespace gpsemu::nmea {

/// Longest sentence accepted, in characters from '$' to the last checksum digit (CR LF excluded).
/// The standard allows 82 including CR LF; some real receivers write longer ones.
inline constexpr std::size_t max_parse_chars = 120;

/// Why a line or a sentence was rejected.
enum class ParseError {
  missing_dollar,      ///< the line does not start with '$'
  too_long,            ///< more than max_parse_chars characters
  bad_character,       ///< a byte outside printable ASCII (0x20..0x7E), or a '$' inside the sentence
  missing_checksum,    ///< no '*'
  malformed_checksum,  ///< '*' not followed by exactly two hex digits (either case) and the line end
  bad_checksum,        ///< the checksum does not match the XOR of the bytes between '$' and '*'
  bad_address,         ///< the address ("GPGGA") is not 3 or more upper-case letters or digits
  wrong_type,          ///< e.g. parse_gga() given an RMC
  too_few_fields,      ///< fewer fields than the sentence type requires
  malformed_field,     ///< a field that cannot be read: "48x7.038", minutes >= 60, 30 February...
};

/// Snake-case name of `error` ("bad_checksum"), for messages.
[[nodiscard]] std::string_view to_string(ParseError error);

/// True when every character of `text` is an ASCII digit (also when `text` is empty).
[[nodiscard]] bool all_digits(std::string_view text);

/// Either a value or the ParseError that prevented it (std::expected is C++23).
template <class T>
class Result {
 public:
  Result(T value) : state_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  Result(ParseError error) : state_(error) {}    // NOLINT(google-explicit-constructor)

  [[nodiscard]] bool ok() const { return std::holds_alternative<T>(state_); }
  explicit operator bool() const { return ok(); }
  /// The value; throws std::bad_variant_access when !ok().
  [[nodiscard]] const T& value() const& { return std::get<T>(state_); }
  [[nodiscard]] T value() && { return std::get<T>(std::move(state_)); }
  [[nodiscard]] const T* operator->() const { return &value(); }
  [[nodiscard]] const T& operator*() const& { return value(); }
  /// The error, or nullopt when ok().
  [[nodiscard]] std::optional<ParseError> error() const {
    if (ok()) return std::nullopt;
    return std::get<ParseError>(state_);
  }

 private:
  std::variant<T, ParseError> state_;
};

/// One framed sentence with a valid checksum, split into fields.
struct Sentence {
  std::string talker;  ///< "GP", "GN", ...; "P" for proprietary sentences ("$PUBX" is "P" + "UBX")
  std::string type;    ///< "GGA", "RMC", ...
  std::vector<std::string> fields;  ///< fields after the address, "*hh" excluded; empty field = ""
};

/// Checks and splits one line "$GPGGA,...*hh". Trailing CR and LF are ignored; the checksum is
/// required, hex digits of either case are accepted.
[[nodiscard]] Result<Sentence> parse_sentence(std::string_view line);

/// A GGA's values. Empty fields are nullopt, never 0.
struct GgaData {
  std::optional<std::chrono::milliseconds> time_of_day;  ///< since UTC midnight (truncated to ms)
  FixQuality quality = FixQuality::none;  ///< field 6 (0..6; an empty field is none)
  std::optional<double> lat_deg;          ///< latitude, degrees, north positive
  std::optional<double> lon_deg;          ///< longitude, degrees, east positive
  std::optional<int> satellites;          ///< satellites used
  std::optional<double> hdop;             ///< horizontal dilution of precision
  std::optional<double> alt_msl_m;        ///< altitude above mean sea level (metres)
  std::optional<double> geoid_sep_m;      ///< geoid separation (metres)
  int minute_decimals = 0;  ///< decimals of the latitude minutes as written; 0 when no latitude
};

/// Reads a GGA (any talker). Needs the 12 fields up to the geoid separation's unit; DGPS age and
/// station are optional. Units other than "M" and quality values outside 0..6 are malformed.
[[nodiscard]] Result<GgaData> parse_gga(const Sentence& sentence);

/// An RMC's values. Empty fields are nullopt, never 0.
struct RmcData {
  std::optional<std::chrono::milliseconds> time_of_day;  ///< since UTC midnight (truncated to ms)
  std::optional<std::chrono::year_month_day> date;       ///< yy < 80 is 20yy, else 19yy
  bool status_active = false;                   ///< status 'A' (valid); 'V' or empty is false
  std::optional<double> lat_deg;                ///< latitude, degrees, north positive
  std::optional<double> lon_deg;                ///< longitude, degrees, east positive
  std::optional<double> speed_mps;              ///< speed over ground (metres per second)
  std::optional<double> course_deg_true;        ///< course over ground, degrees true
  std::optional<double> magnetic_variation_deg;  ///< degrees, east positive
  std::optional<char> mode;        ///< NMEA 2.3+ mode indicator (A D E F M N P R S)
  std::optional<char> nav_status;  ///< NMEA 4.1 navigational status (S C U V)
  int minute_decimals = 0;  ///< decimals of the latitude minutes as written; 0 when no latitude
};

/// Reads an RMC (any talker) of NMEA 2.0 (11 fields), 2.3 (12, mode) or 4.1 (13, nav status).
[[nodiscard]] Result<RmcData> parse_rmc(const Sentence& sentence);

/// The UTC time of an RMC's date and time of day, when both are present.
[[nodiscard]] std::optional<UtcTime> utc_time(const RmcData& rmc);

/// What a StreamReader has seen. Every byte except CR and LF outside sentences is counted once:
/// in a sentence (ok, bad checksum or malformed), in a comment line, or as garbage.
struct StreamStats {
  std::uint64_t sentences_ok = 0;   ///< sentences returned
  std::uint64_t bad_checksum = 0;   ///< complete sentences whose checksum does not match
  std::uint64_t malformed = 0;      ///< no or malformed checksum, bad address, bad characters,
                                    ///< too long, or cut short by '$'/binary after a ',' or '*'
  std::uint64_t garbage_bytes = 0;  ///< bytes outside any sentence or comment (binary frames...)
  std::uint64_t comment_lines = 0;  ///< lines starting with '#' (gpsd log headers)
};

/// Splits a receiver's raw byte stream into checked sentences, incrementally: chunks may end
/// anywhere, even inside a sentence. The stream may interleave binary protocols (UBX, CASIC,
/// random bytes that may contain '$'), '#' comment lines, empty lines and CR LF, LF or CR endings.
/// A candidate sentence starts at '$' and ends at CR or LF; it is abandoned at a byte outside
/// printable ASCII, at another '$', or past max_parse_chars (the rest of that line is garbage).
/// An abandoned candidate that never reached a ',' or '*' was garbage, otherwise it is malformed.
/// Memory is bounded by max_parse_chars whatever the input.
class StreamReader {
 public:
  /// Consumes `bytes` and returns the sentences they complete, in stream order.
  [[nodiscard]] std::vector<Sentence> feed(std::string_view bytes);
  /// End of the stream: a last sentence or comment without a line end is taken as ended.
  [[nodiscard]] std::optional<Sentence> finish();
  [[nodiscard]] const StreamStats& stats() const { return stats_; }

 private:
  enum class State { between, sentence, comment, rest_of_line };
  void consume(char byte, std::vector<Sentence>& out);
  void start_sentence();
  void end_sentence(std::vector<Sentence>& out);
  void abandon_sentence();

  State state_ = State::between;
  bool at_line_start_ = true;   // '#' only starts a comment at the start of a line
  std::string candidate_;       // from '$', never longer than max_parse_chars
  std::size_t comment_chars_ = 0;
  StreamStats stats_;
};

}  // namespace gpsemu::nmea
