// libFuzzer target for nmea/: arbitrary bytes through StreamReader (in chunks the input chooses),
// parse_sentence, parse_gga and parse_rmc; and Fix values made from the same bytes through
// format_gga/format_rmc and back. Traps when an invariant breaks:
//  - StreamReader returns exactly stats().sentences_ok sentences, each of which re-frames and
//    re-parses to the same fields;
//  - every formatted sentence parses, and the position comes back within half a unit.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"

namespace {

using namespace gpsemu::nmea;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

void check_sentence(const Sentence& sentence) {
  std::string body = sentence.talker + sentence.type;
  for (const std::string& field : sentence.fields) body += "," + field;
  const Result<Sentence> again = parse_sentence(frame(body));
  require(again.ok() && again->fields == sentence.fields && again->type == sentence.type);
  (void)parse_gga(sentence);
  (void)parse_rmc(sentence);
}

void fuzz_reader(std::string_view input) {
  if (input.empty()) return;
  const std::size_t chunk = 1 + static_cast<unsigned char>(input[0]) % 97;
  StreamReader reader;
  std::uint64_t produced = 0;
  for (std::size_t begin = 0; begin < input.size(); begin += chunk) {
    for (const Sentence& s : reader.feed(input.substr(begin, chunk))) {
      check_sentence(s);
      ++produced;
    }
  }
  if (const auto last = reader.finish()) {
    check_sentence(*last);
    ++produced;
  }
  require(produced == reader.stats().sentences_ok);
}

template <class T>
T take(std::string_view& input) {
  T value{};
  const std::size_t n = std::min(sizeof(T), input.size());
  std::memcpy(&value, input.data(), n);
  input.remove_prefix(n);
  return value;
}

void fuzz_format(std::string_view input) {
  Fix fix;
  // Times within years 1970..2079 (RMC's two-digit year reads back as 1980..2079 either way).
  fix.time_utc = UtcTime{std::chrono::milliseconds{take<std::uint64_t>(input) % 3'470'000'000'000ULL}};
  fix.quality = static_cast<FixQuality>(take<std::uint8_t>(input) % 7);
  fix.lat_deg = take<double>(input);
  fix.lon_deg = take<double>(input);
  fix.alt_msl_m = take<double>(input);
  fix.geoid_sep_m = take<double>(input);
  fix.speed_mps = take<double>(input);
  if (take<std::uint8_t>(input) % 2 == 0) fix.course_deg_true = take<double>(input);
  fix.satellites_used = take<int>(input);
  fix.hdop = take<double>(input);
  FormatOptions options;
  options.talker = take<std::uint8_t>(input) % 2 == 0 ? "GP" : "GN";
  options.minute_decimals = take<std::int8_t>(input);
  options.time_decimals = take<std::int8_t>(input);
  options.version = take<std::uint8_t>(input) % 2 == 0 ? NmeaVersion::v2_3 : NmeaVersion::v4_1;

  const Result<Sentence> gga_sentence = parse_sentence(format_gga(fix, options));
  const Result<Sentence> rmc_sentence = parse_sentence(format_rmc(fix, options));
  require(gga_sentence.ok() && rmc_sentence.ok());
  const Result<GgaData> gga = parse_gga(*gga_sentence);
  const Result<RmcData> rmc = parse_rmc(*rmc_sentence);
  require(gga.ok() && rmc.ok());
  require(rmc->status_active == fix.has_fix());
  if (!fix.has_fix()) return;
  const int decimals = std::clamp(options.minute_decimals, 1, 8);
  const double half_unit_deg = 0.5 / (60.0 * std::pow(10.0, decimals)) + 1e-9;
  if (std::isfinite(fix.lat_deg) && std::fabs(fix.lat_deg) <= 90.0) {
    require(gga->lat_deg && std::fabs(*gga->lat_deg - fix.lat_deg) <= half_unit_deg);
  }
  if (std::isfinite(fix.lon_deg) && std::fabs(fix.lon_deg) <= 180.0) {
    require(gga->lon_deg && std::fabs(*gga->lon_deg - fix.lon_deg) <= half_unit_deg);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  fuzz_reader(input);
  (void)parse_sentence(input);
  fuzz_format(input);
  return 0;
}
