// Test support for the fuzz targets of pose inputs (trajectory CSV, waypoint CSV): checks on local
// East/North/Up positions, and the local frame they are read in (the default --origin).
#pragma once

#include <algorithm>
#include <cmath>

#include "emulator/model/enu.hpp"
#include "emulator/model/geo.hpp"

namespace gpsemu::test {

/// Every coordinate is finite.
inline bool finite(const Enu& e) {
  return std::isfinite(e.east_m) && std::isfinite(e.north_m) && std::isfinite(e.up_m);
}

/// The largest coordinate's magnitude (metres).
inline double norm_inf(const Enu& e) {
  return std::max({std::abs(e.east_m), std::abs(e.north_m), std::abs(e.up_m)});
}

/// The local frame about gpsemu's default origin (43.0725, -89.4125, 260 m).
inline const LocalFrame& frame() {
  static const LocalFrame f(Geodetic{43.0725, -89.4125, 260.0});
  return f;
}

}  // namespace gpsemu::test
