// What a receiver tracks (docs/sky.md): its systems and signals, channel count, elevation mask, the
// C/N0 a signal needs to be used, and the user equivalent range error (UERE) that turns a DOP into
// the accuracy it reports. Pure values; each receiver model's are a column of the receiver table
// (emulator/model/receiver_models.hpp).
#pragma once

#include <cstdint>
#include <initializer_list>

#include "nmea/fix.hpp"

namespace gpsemu::sky {

/// A set of GNSS systems (bit = 1 << u-blox gnssId).
class SystemSet {
 public:
  constexpr SystemSet() = default;
  constexpr SystemSet(std::initializer_list<nmea::GnssSystem> systems) {
    for (const auto s : systems) bits_ |= bit(s);
  }
  [[nodiscard]] constexpr bool contains(nmea::GnssSystem s) const { return (bits_ & bit(s)) != 0; }
  [[nodiscard]] constexpr std::uint8_t bits() const { return bits_; }
  [[nodiscard]] int count() const { return __builtin_popcount(bits_); }

 private:
  static constexpr std::uint8_t bit(nmea::GnssSystem s) { return static_cast<std::uint8_t>(1u << static_cast<unsigned>(s)); }
  std::uint8_t bits_ = 0;
};

/// How a receiver model tracks the sky.
struct Tracking {
  SystemSet systems;             ///< systems tracked as shipped
  bool dual_band = false;        ///< a second signal per satellite (F9P: L2C, L2OF, E5b, B2I)
  int channels = 72;             ///< tracking channels; a dual-band satellite takes two
  double elevation_mask_deg = 5.0;  ///< below it a satellite is tracked but not used (CFG-NAV5 minElev)
  double cn0_threshold_dbhz = 20.0; ///< a signal weaker than this is not used
  /// Autonomous UERE (metres, 1 sigma): HDOP x UERE is the horizontal accuracy reported.
  double uere_m = 1.5;
};

}  // namespace gpsemu::sky
