// Appending numbers and the checksum to sentence text without a formatting library: the building
// blocks of the per-epoch formatters (GGA, RMC and the field helpers), which run a million times a
// second in --fast mode, where fmt's run-time format-string parsing was most of the cost. Internal
// to nmea/. Pure; no allocation beyond the output string's own growth.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace gpsemu::nmea::text {

/// 10^exponent for exponent 0..18.
[[nodiscard]] constexpr std::uint64_t pow10(int exponent) {
  std::uint64_t result = 1;
  for (int i = 0; i < exponent; ++i) result *= 10;
  return result;
}

/// Appends `value` in decimal, zero padded on the left to at least `min_digits` (at most 20)
/// digits: append_uint(out, 7, 2) appends "07".
inline void append_uint(std::string& out, std::uint64_t value, int min_digits = 1) {
  char digits[20];
  char* const end = digits + sizeof digits;
  char* p = end;
  do {
    *--p = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0);
  while (end - p < min_digits && p > digits) *--p = '0';
  // A few characters: push_back (inlined) costs less than append's out-of-line copy.
  for (; p < end; ++p) out.push_back(*p);
}

/// Appends the fixed-point number `units` x 10^-decimals with exactly `decimals` (0..18) digits
/// after the point and no point when `decimals` is 0: (-1230, 2) appends "-12.30", (5, 3) "0.005".
inline void append_scaled(std::string& out, std::int64_t units, int decimals) {
  if (units < 0) out += '-';
  const std::uint64_t magnitude =
      units < 0 ? std::uint64_t{0} - static_cast<std::uint64_t>(units) : static_cast<std::uint64_t>(units);
  if (decimals <= 0) {
    append_uint(out, magnitude);
    return;
  }
  const std::uint64_t scale = pow10(decimals);
  append_uint(out, magnitude / scale);
  out += '.';
  append_uint(out, magnitude % scale, decimals);
}

/// Ends a sentence: `sentence` holds "$" + body; appends "*hh\r\n", hh the XOR of the body's bytes
/// in two upper-case hex digits.
inline void close_sentence(std::string& sentence) {
  static constexpr std::string_view hex = "0123456789ABCDEF";
  unsigned char sum = 0;
  for (std::size_t i = 1; i < sentence.size(); ++i) sum ^= static_cast<unsigned char>(sentence[i]);
  const char tail[] = {'*', hex[sum >> 4], hex[sum & 0x0f], '\r', '\n'};
  sentence.append(tail, sizeof tail);
}

}  // namespace gpsemu::nmea::text
