// Little-endian payload fields of UBX messages: a writer that appends U1/I2/U4/R4... to a byte
// string and a reader that takes them from a payload at an offset. Pure, header-only; a read past
// the end yields 0 (callers check payload lengths before reading).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace gpsemu::ubx {

/// Appends unsigned `value` as `bytes` little-endian bytes.
inline void put_le(std::string& out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xFF));
}
inline void put_u1(std::string& out, std::uint32_t v) { put_le(out, v, 1); }
inline void put_u2(std::string& out, std::uint32_t v) { put_le(out, v, 2); }
inline void put_u4(std::string& out, std::uint32_t v) { put_le(out, v, 4); }
inline void put_i1(std::string& out, std::int32_t v) { put_le(out, static_cast<std::uint8_t>(v), 1); }
inline void put_i2(std::string& out, std::int32_t v) { put_le(out, static_cast<std::uint16_t>(v), 2); }
inline void put_i4(std::string& out, std::int32_t v) { put_le(out, static_cast<std::uint32_t>(v), 4); }
inline void put_r4(std::string& out, float v) { put_u4(out, std::bit_cast<std::uint32_t>(v)); }
/// `count` zero bytes (reserved fields).
inline void put_zeros(std::string& out, std::size_t count) { out.append(count, '\0'); }
/// `text` in a fixed-size, zero-padded character field of `size` bytes (cut when longer).
inline void put_chars(std::string& out, std::string_view text, std::size_t size) {
  const std::size_t n = text.size() < size ? text.size() : size;
  out.append(text.substr(0, n));
  out.append(size - n, '\0');
}

/// Unsigned little-endian value of `bytes` bytes at `offset` of `payload` (0 past the end).
[[nodiscard]] inline std::uint64_t get_le(std::string_view payload, std::size_t offset, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) {
    const std::size_t at = offset + static_cast<std::size_t>(i);
    if (at >= payload.size()) return 0;
    v |= static_cast<std::uint64_t>(static_cast<unsigned char>(payload[at])) << (8 * i);
  }
  return v;
}
[[nodiscard]] inline std::uint8_t get_u1(std::string_view p, std::size_t at) {
  return static_cast<std::uint8_t>(get_le(p, at, 1));
}
[[nodiscard]] inline std::uint16_t get_u2(std::string_view p, std::size_t at) {
  return static_cast<std::uint16_t>(get_le(p, at, 2));
}
[[nodiscard]] inline std::uint32_t get_u4(std::string_view p, std::size_t at) {
  return static_cast<std::uint32_t>(get_le(p, at, 4));
}
[[nodiscard]] inline std::int32_t get_i4(std::string_view p, std::size_t at) {
  return static_cast<std::int32_t>(get_u4(p, at));
}

}  // namespace gpsemu::ubx
