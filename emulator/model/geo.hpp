// Local East/North/Up metres <-> WGS84 geodetic, about a fixed origin (GeographicLib's
// ellipsoidal LocalCartesian). Fields are named, so nobody has to remember an order.
#pragma once

#include <GeographicLib/LocalCartesian.hpp>

#include "emulator/model/enu.hpp"

namespace gpsemu {

/// A WGS84 position. `alt_m` is the height the caller works in (this project: above MSL, with a
/// constant geoid separation applied only when formatting GGA).
struct Geodetic {
  double lat_deg = 0.0;  ///< latitude (degrees), [-90, 90]
  double lon_deg = 0.0;  ///< longitude (degrees), [-180, 180)
  double alt_m = 0.0;    ///< altitude (metres)
};

class LocalFrame {
 public:
  /// Throws std::invalid_argument when the origin latitude is outside [-90, 90].
  explicit LocalFrame(const Geodetic& origin);

  [[nodiscard]] Enu to_enu(const Geodetic& point) const;
  [[nodiscard]] Geodetic to_geodetic(const Enu& point) const;
  [[nodiscard]] const Geodetic& origin() const { return origin_; }

 private:
  Geodetic origin_;
  GeographicLib::LocalCartesian frame_;
};

/// Normalises a longitude to [-180, 180).
[[nodiscard]] double wrap_lon_deg(double lon_deg);

}  // namespace gpsemu
