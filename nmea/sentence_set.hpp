// Which sentence types an epoch carries, and the order a receiver writes them in. u-blox (M8, F9)
// writes RMC, VTG, GGA, GSA, GSV..., GLL, then the optional GST and ZDA (ZED-F9P log in
// data/real: RMC VTG GGA GLL with GSA/GSV off); that is the order here whatever order the user
// lists them in. Pure value types, no allocation.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace gpsemu::nmea {

/// One sentence type. The enumerators are in receiver (u-blox) output order.
enum class SentenceType : std::uint8_t { rmc, vtg, gga, gsa, gsv, gll, gst, zda, hdt, ths };

/// Every type, in output order.
/// HDT and THS (true heading; a dual-antenna receiver's) come last; they are not u-blox F9P messages.
inline constexpr std::array<SentenceType, 10> all_sentence_types = {
    SentenceType::rmc, SentenceType::vtg, SentenceType::gga, SentenceType::gsa, SentenceType::gsv,
    SentenceType::gll, SentenceType::gst, SentenceType::zda, SentenceType::hdt, SentenceType::ths};

/// "RMC", "VTG", ...
[[nodiscard]] constexpr std::string_view sentence_name(SentenceType type) {
  constexpr std::array<std::string_view, 10> names = {"RMC", "VTG", "GGA", "GSA", "GSV",
                                                      "GLL", "GST", "ZDA", "HDT", "THS"};
  return names[static_cast<std::size_t>(type)];
}

/// The type named `text` (three upper-case letters, "GGA"); nullopt for anything else.
[[nodiscard]] constexpr std::optional<SentenceType> sentence_type_from_name(std::string_view text) {
  for (const SentenceType t : all_sentence_types) {
    if (sentence_name(t) == text) return t;
  }
  return std::nullopt;
}

/// A set of sentence types; iterating it (for_each) visits them in output order.
class SentenceSet {
 public:
  constexpr SentenceSet() = default;
  /// u-blox's factory default: RMC, VTG, GGA, GSA, GSV, GLL (GST and ZDA off).
  [[nodiscard]] static constexpr SentenceSet ublox_default() {
    SentenceSet s;
    for (const SentenceType t : {SentenceType::rmc, SentenceType::vtg, SentenceType::gga, SentenceType::gsa,
                                 SentenceType::gsv, SentenceType::gll}) {
      s.insert(t);
    }
    return s;
  }
  constexpr void insert(SentenceType type) { bits_ |= bit(type); }
  [[nodiscard]] constexpr bool contains(SentenceType type) const { return (bits_ & bit(type)) != 0; }
  [[nodiscard]] constexpr bool empty() const { return bits_ == 0; }
  /// Calls `f(type)` for each type in the set, in output order.
  template <class F>
  constexpr void for_each(F&& f) const {
    for (const SentenceType t : all_sentence_types) {
      if (contains(t)) f(t);
    }
  }
  friend constexpr bool operator==(SentenceSet, SentenceSet) = default;

 private:
  static constexpr std::uint16_t bit(SentenceType type) {
    return static_cast<std::uint16_t>(1u << static_cast<unsigned>(type));
  }
  std::uint16_t bits_ = 0;
};

}  // namespace gpsemu::nmea
