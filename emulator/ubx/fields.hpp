// UBX payloads as named fields (pyubx2's message tables, PX4's packed ubx.h
// structs): a layout is a list of fields with the interface description's names
// and types (U1 I1 X1 U2 I2 X2 U4 I4 X4 R4 R8 CH, `count` of them for an
// array), and a PayloadWriter fills a zeroed payload by field name. A name the
// layout lacks, or a floating-point value for an integer field (and the other
// way round), does not compile. Integers are written little-endian, two's
// complement, cut to the field's size as the put_* writers of bytes.hpp do.
// Pure, header-only.
#pragma once

#include <algorithm>
#include <bit>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace gpsemu::ubx {

/// The interface description's field types; CH is one character of a text
/// field.
enum class FieldType : std::uint8_t { U1, I1, X1, U2, I2, X2, U4, I4, X4, R4, R8, CH };

[[nodiscard]] constexpr std::size_t field_type_bytes(FieldType t) {
  switch (t) {
    case FieldType::U2:
    case FieldType::I2:
    case FieldType::X2: return 2;
    case FieldType::U4:
    case FieldType::I4:
    case FieldType::X4:
    case FieldType::R4: return 4;
    case FieldType::R8: return 8;
    default: return 1;
  }
}
[[nodiscard]] constexpr std::string_view field_type_name(FieldType t) {
  constexpr std::string_view names[] = {"U1", "I1", "X1", "U2", "I2", "X2", "U4", "I4", "X4", "R4", "R8", "CH"};
  return names[static_cast<std::size_t>(t)];
}
[[nodiscard]] constexpr bool is_real(FieldType t) { return t == FieldType::R4 || t == FieldType::R8; }

/// One field of a payload: its name ("iTOW"; "reserved0" for reserved bytes),
/// type, how many (an array such as VP U1[17]) and unit or scale as the
/// interface description gives it.
struct Field {
  std::string_view name;
  FieldType type = FieldType::U1;
  std::size_t count = 1;
  std::string_view unit = {};
  [[nodiscard]] constexpr std::size_t bytes() const { return field_type_bytes(type) * count; }
};

using Layout = std::span<const Field>;

/// Payload bytes of a layout (of one repeated block, for the blocks of NAV-SAT
/// and the like).
[[nodiscard]] constexpr std::size_t layout_bytes(Layout layout) {
  std::size_t n = 0;
  for (const Field& f : layout) n += f.bytes();
  return n;
}
/// Index of field `name` in `layout`, layout.size() when it has none.
[[nodiscard]] constexpr std::size_t field_index(Layout layout, std::string_view name) {
  for (std::size_t i = 0; i < layout.size(); ++i) {
    if (layout[i].name == name) return i;
  }
  return layout.size();
}
/// Byte offset of field `index` of `layout`.
[[nodiscard]] constexpr std::size_t field_offset(Layout layout, std::size_t index) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < index; ++i) n += layout[i].bytes();
  return n;
}

/// A field name as a template argument: set<"iTOW">(...).
template <std::size_t N>
struct FieldName {
  char chars[N]{};
  consteval FieldName(const char (&s)[N]) { std::copy_n(s, N, chars); }  // NOLINT: implicit by design
  [[nodiscard]] constexpr std::string_view view() const { return {chars, N - 1}; }
};

/// Fills a payload of layout `L` (a constexpr array of Field) by field name;
/// unset fields are 0.
template <const auto& L>
class PayloadWriter {
 public:
  PayloadWriter() : bytes_(layout_bytes(L), '\0') {}

  /// Sets integer field `Name` (element `element` of an array field).
  template <FieldName Name, std::integral T>
  PayloadWriter& set(T value, std::size_t element = 0) {
    constexpr std::size_t i = index_of<Name>();
    static_assert(!is_real(L[i].type), "a floating-point field takes a float or double");
    put(field_offset(L, i) + element * field_type_bytes(L[i].type), static_cast<std::uint64_t>(value),
        field_type_bytes(L[i].type));
    return *this;
  }
  /// Sets floating-point field `Name` (R4 as float, R8 as double).
  template <FieldName Name, std::floating_point T>
  PayloadWriter& set(T value, std::size_t element = 0) {
    constexpr std::size_t i = index_of<Name>();
    static_assert(is_real(L[i].type), "an integer field takes an integer");
    const std::size_t at = field_offset(L, i) + element * field_type_bytes(L[i].type);
    if constexpr (L[i].type == FieldType::R4) {
      put(at, std::bit_cast<std::uint32_t>(static_cast<float>(value)), 4);
    } else {
      put(at, std::bit_cast<std::uint64_t>(static_cast<double>(value)), 8);
    }
    return *this;
  }
  /// Sets text field `Name` (CH[count]): `text` zero-padded, cut at the field's
  /// size.
  template <FieldName Name>
  PayloadWriter& set_text(std::string_view text) {
    constexpr std::size_t i = index_of<Name>();
    static_assert(L[i].type == FieldType::CH, "set_text() fills a CH field");
    const std::size_t n = std::min(text.size(), L[i].count);
    std::copy_n(text.begin(), n, bytes_.begin() + static_cast<std::ptrdiff_t>(field_offset(L, i)));
    return *this;
  }
  [[nodiscard]] const std::string& bytes() const& { return bytes_; }
  [[nodiscard]] std::string bytes() && { return std::move(bytes_); }

 private:
  template <FieldName Name>
  static consteval std::size_t index_of() {
    constexpr std::size_t i = field_index(L, Name.view());
    static_assert(i < std::size(L), "the payload layout has no field of this name");
    return i;
  }
  void put(std::size_t at, std::uint64_t value, std::size_t size) {
    for (std::size_t b = 0; b < size; ++b) bytes_[at + b] = static_cast<char>((value >> (8 * b)) & 0xFF);
  }
  std::string bytes_;
};

}  // namespace gpsemu::ubx
