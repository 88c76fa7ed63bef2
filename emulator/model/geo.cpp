#include "emulator/model/geo.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace gpsemu {

LocalFrame::LocalFrame(const Geodetic& origin) : origin_(origin) {
  if (!(origin.lat_deg >= -90.0 && origin.lat_deg <= 90.0)) {
    throw std::invalid_argument("origin latitude " + std::to_string(origin.lat_deg) +
                                " is outside [-90, 90] degrees");
  }
  if (!std::isfinite(origin.lon_deg) || !std::isfinite(origin.alt_m)) {
    throw std::invalid_argument("origin longitude and altitude must be finite numbers");
  }
  origin_.lon_deg = wrap_lon_deg(origin.lon_deg);
  frame_.Reset(origin_.lat_deg, origin_.lon_deg, origin_.alt_m);
}

Enu LocalFrame::to_enu(const Geodetic& point) const {
  Enu out;
  frame_.Forward(point.lat_deg, point.lon_deg, point.alt_m, out.east_m, out.north_m, out.up_m);
  return out;
}

Geodetic LocalFrame::to_geodetic(const Enu& point) const {
  Geodetic out;
  frame_.Reverse(point.east_m, point.north_m, point.up_m, out.lat_deg, out.lon_deg, out.alt_m);
  out.lon_deg = wrap_lon_deg(out.lon_deg);
  return out;
}

double wrap_lon_deg(double lon_deg) {
  double x = lon_deg + 180.0;
  // fmod returns an x already in [0, 360) unchanged: the call is skipped then (every longitude
  // GeographicLib returns).
  if (!(x >= 0.0 && x < 360.0)) {
    x = std::fmod(x, 360.0);
    if (x < 0.0) x += 360.0;
  }
  return x - 180.0;
}

}  // namespace gpsemu
