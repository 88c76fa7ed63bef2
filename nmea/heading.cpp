// HDT and THS (see heading.hpp).
#include "nmea/heading.hpp"

#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "nmea/fields.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {

/// "123.45" -> 123.45; empty -> nullopt; anything else (or outside [0, 360]) -> malformed.
Result<std::optional<double>> heading_field(const std::string& text) {
  if (text.empty()) return std::optional<double>{};
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size() || !(value >= 0.0 && value <= 360.0)) {
    return ParseError::malformed_field;
  }
  return std::optional<double>{value};
}

Result<HeadingSentence> parse_heading(const Sentence& sentence, std::string_view type) {
  if (sentence.type != type) return ParseError::wrong_type;
  if (sentence.fields.size() < 2) return ParseError::too_few_fields;
  const auto heading = heading_field(sentence.fields[0]);
  if (!heading) return *heading.error();
  const std::string& mode = sentence.fields[1];
  if (mode.size() != 1) return ParseError::malformed_field;
  return HeadingSentence{heading.value(), mode[0]};
}

}  // namespace

std::optional<double> reported_heading_deg(const Fix& fix) {
  if (!fix.has_fix() || !fix.heading_deg_true || !std::isfinite(*fix.heading_deg_true)) return std::nullopt;
  return fix.heading_deg_true;
}

std::string format_hdt(const Fix& fix, const FormatOptions& options) {
  return frame(fmt::format("{}HDT,{},T", options.talker, fields::format_course(reported_heading_deg(fix))));
}

std::string format_ths(const Fix& fix, const FormatOptions& options) {
  const auto heading = reported_heading_deg(fix);
  return frame(fmt::format("{}THS,{},{}", options.talker, fields::format_course(heading), heading ? 'A' : 'V'));
}

Result<HeadingSentence> parse_hdt(const Sentence& sentence) {
  auto h = parse_heading(sentence, "HDT");
  if (h && h->mode != 'T') return ParseError::malformed_field;
  return h;
}

Result<HeadingSentence> parse_ths(const Sentence& sentence) {
  auto h = parse_heading(sentence, "THS");
  if (h && std::string_view("AEMSV").find(h->mode) == std::string_view::npos) return ParseError::malformed_field;
  return h;
}

}  // namespace gpsemu::nmea
