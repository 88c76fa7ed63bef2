// A place that triggers a fault (`where = "circle:LAT,LON,RADIUS_M"` or
// `"polygon:LAT,LON;LAT,LON;..."`): the fault starts when the truth enters it and ends when the
// truth leaves it (or after its duration). Pure geometry on WGS84 latitudes and longitudes.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "emulator/model/geo.hpp"

namespace gpsemu::faults {

struct Area {
  enum class Shape { circle, polygon };
  Shape shape = Shape::circle;
  /// circle: its centre; polygon: its corners in order (at least 3), degrees.
  std::vector<Geodetic> points;
  double radius_m = 0.0;  ///< circle: radius (metres, great-circle distance)

  /// Whether `p` is inside (on the circle's edge counts as inside). Altitude is ignored.
  [[nodiscard]] bool contains(const Geodetic& p) const;
  /// The text it was parsed from, normalised ("circle:47.1,8.2,300").
  [[nodiscard]] std::string text() const;
};

/// Parses "circle:LAT,LON,RADIUS_M" or "polygon:LAT,LON;LAT,LON;LAT,LON[;...]". Throws
/// std::invalid_argument ("where: ...") naming what was wrong.
[[nodiscard]] Area parse_area(std::string_view text);

/// Great-circle distance between two positions (metres, on a sphere of the WGS84 mean radius).
[[nodiscard]] double surface_distance_m(const Geodetic& a, const Geodetic& b);

}  // namespace gpsemu::faults
