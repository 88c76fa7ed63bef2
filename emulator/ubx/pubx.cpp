// $PUBX,40 and $PUBX,41 (see pubx.hpp).
#include "emulator/ubx/pubx.hpp"

#include <charconv>
#include <string_view>

namespace gpsemu::ubx {
namespace {

bool is_pubx(const nmea::Sentence& s, std::string_view number, std::size_t fields) {
  return s.talker == "P" && s.type == "UBX" && s.fields.size() >= fields && s.fields[0] == number;
}

std::optional<std::uint32_t> read_uint(const std::string& text, int base, std::uint32_t max) {
  std::uint32_t v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v, base);
  if (text.empty() || ec != std::errc{} || ptr != end || v > max) return std::nullopt;
  return v;
}

}  // namespace

std::optional<Pubx40> parse_pubx40(const nmea::Sentence& sentence) {
  if (!is_pubx(sentence, "40", 7)) return std::nullopt;
  Pubx40 cmd;
  cmd.message = sentence.fields[1];
  if (cmd.message.size() != 3) return std::nullopt;
  for (std::size_t port = 0; port < 5; ++port) {
    const auto rate = read_uint(sentence.fields[2 + port], 10, 255);
    if (!rate) return std::nullopt;
    cmd.rates[port] = static_cast<std::uint8_t>(*rate);
  }
  return cmd;
}

std::optional<Pubx41> parse_pubx41(const nmea::Sentence& sentence) {
  if (!is_pubx(sentence, "41", 5)) return std::nullopt;
  const auto port = read_uint(sentence.fields[1], 10, 4);
  const auto in = read_uint(sentence.fields[2], 16, 0xFFFF);
  const auto out = read_uint(sentence.fields[3], 16, 0xFFFF);
  const auto baud = read_uint(sentence.fields[4], 10, 4'000'000);
  if (!port || !in || !out || !baud || *baud == 0) return std::nullopt;
  return Pubx41{static_cast<Port>(*port), static_cast<std::uint16_t>(*in), static_cast<std::uint16_t>(*out), *baud};
}

}  // namespace gpsemu::ubx
