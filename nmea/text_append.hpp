// Writing numbers and the checksum into sentence text without a formatting library: the building
// blocks of the per-epoch formatters (GGA, RMC and the field helpers), which run a million times a
// second in --fast mode, where fmt's run-time format-string parsing was most of the cost. Internal
// to nmea/. Pure; no allocation beyond the output string's own growth.
//
// The put_* functions write at `p` into a buffer the caller has sized (no bounds checks) and return
// the end of what they wrote; the append_* ones append to a std::string.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace gpsemu::nmea::text {

/// 10^0 .. 10^19.
inline constexpr std::array<std::uint64_t, 20> powers_of_10 = [] {
  std::array<std::uint64_t, 20> powers{};
  std::uint64_t power = 1;
  for (std::uint64_t& p : powers) {
    p = power;
    power *= 10;
  }
  return powers;
}();

/// 10^exponent for exponent 0..19.
[[nodiscard]] constexpr std::uint64_t pow10(int exponent) { return powers_of_10[static_cast<std::size_t>(exponent)]; }

/// `x` rounded half away from zero, as std::llround(x), for |x| < 2^62 (callers check; NaN is not
/// allowed). Inline: the truncation toward zero and the remainder x - trunc(x) are exact in
/// doubles, so no libm call is needed.
[[nodiscard]] inline std::int64_t round_half_away(double x) {
  auto units = static_cast<std::int64_t>(x);  // toward zero
  const double rest = x - static_cast<double>(units);
  if (rest >= 0.5) ++units;
  if (rest <= -0.5) --units;
  return units;
}

/// How many decimal digits `value` has (1 for 0).
[[nodiscard]] inline int decimal_digits(std::uint64_t value) {
  int digits = 1;
  while (digits < 20 && value >= powers_of_10[static_cast<std::size_t>(digits)]) ++digits;
  return digits;
}

/// Writes the `count` (1..20) low decimal digits of `value`, zero padded: (7, 2) writes "07".
inline char* put_digits(char* p, std::uint64_t value, int count) {
  static constexpr char pairs[] =
      "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
      "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
      "8081828384858687888990919293949596979899";
  char* q = p + count;
  while (q - p >= 2) {
    q -= 2;
    std::memcpy(q, pairs + 2 * (value % 100), 2);
    value /= 100;
  }
  if (q > p) *p = static_cast<char>('0' + value % 10);
  return p + count;
}

/// Writes `value` in decimal, zero padded on the left to at least `min_digits` (at most 20).
inline char* put_uint(char* p, std::uint64_t value, int min_digits = 1) {
  const int digits = decimal_digits(value);
  return put_digits(p, value, digits > min_digits ? digits : min_digits);
}

/// Writes the fixed-point number `units` x 10^-decimals with exactly `decimals` (0..18) digits after
/// the point and no point when `decimals` is 0: (-1230, 2) writes "-12.30", (5, 3) "0.005".
inline char* put_scaled(char* p, std::int64_t units, int decimals) {
  if (units < 0) *p++ = '-';
  const std::uint64_t magnitude =
      units < 0 ? std::uint64_t{0} - static_cast<std::uint64_t>(units) : static_cast<std::uint64_t>(units);
  if (decimals <= 0) return put_uint(p, magnitude);
  const std::uint64_t scale = pow10(decimals);
  p = put_uint(p, magnitude / scale);
  *p++ = '.';
  return put_digits(p, magnitude % scale, decimals);
}

/// Writes `s`. With a literal the length is a constant and the copy is inlined.
inline char* put_chars(char* p, std::string_view s) {
  std::memcpy(p, s.data(), s.size());
  return p + s.size();
}

/// XOR of the bytes in [begin, end), eight at a time.
[[nodiscard]] inline unsigned char xor_bytes(const char* begin, const char* end) {
  std::uint64_t sum = 0;
  for (; end - begin >= 8; begin += 8) {
    std::uint64_t word = 0;
    std::memcpy(&word, begin, sizeof word);
    sum ^= word;
  }
  for (; begin < end; ++begin) sum ^= static_cast<unsigned char>(*begin);
  // Every byte lane of `sum` XORed together: the order of the bytes in a word does not matter.
  sum ^= sum >> 32;
  sum ^= sum >> 16;
  sum ^= sum >> 8;
  return static_cast<unsigned char>(sum);
}

/// Ends a sentence: [sentence, p) holds "$" + body; writes "*hh\r\n", hh the XOR of the body's
/// bytes in two upper-case hex digits. The buffer needs 8 writable bytes at `p`: they are zeroed
/// first, so the body is XORed in whole 8-byte words (zeros do not change an XOR), then overwritten.
inline char* put_checksum(const char* sentence, char* p) {
  static constexpr char hex[] = "0123456789ABCDEF";
  std::memset(p, 0, 8);
  std::uint64_t sum = 0;
  for (const char* word = sentence + 1; word < p; word += 8) {
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, word, sizeof bytes);
    sum ^= bytes;
  }
  sum ^= sum >> 32;
  sum ^= sum >> 16;
  sum ^= sum >> 8;
  const auto checksum = static_cast<unsigned char>(sum);
  const char tail[] = {'*', hex[checksum >> 4], hex[checksum & 0x0f], '\r', '\n'};
  std::memcpy(p, tail, sizeof tail);
  return p + sizeof tail;
}

/// Appends `value` in decimal, zero padded on the left to at least `min_digits` (at most 20)
/// digits: append_uint(out, 7, 2) appends "07".
inline void append_uint(std::string& out, std::uint64_t value, int min_digits = 1) {
  char digits[20];
  out.append(digits, static_cast<std::size_t>(put_uint(digits, value, min_digits) - digits));
}

/// Appends the fixed-point number `units` x 10^-decimals (see put_scaled).
inline void append_scaled(std::string& out, std::int64_t units, int decimals) {
  char digits[48];
  out.append(digits, static_cast<std::size_t>(put_scaled(digits, units, decimals) - digits));
}

/// Ends a sentence: `sentence` holds "$" + body; appends "*hh\r\n" (see put_checksum).
inline void close_sentence(std::string& sentence) {
  char tail[5];
  const unsigned char sum = xor_bytes(sentence.data() + 1, sentence.data() + sentence.size());
  static constexpr char hex[] = "0123456789ABCDEF";
  tail[0] = '*';
  tail[1] = hex[sum >> 4];
  tail[2] = hex[sum & 0x0f];
  tail[3] = '\r';
  tail[4] = '\n';
  sentence.append(tail, sizeof tail);
}

}  // namespace gpsemu::nmea::text
