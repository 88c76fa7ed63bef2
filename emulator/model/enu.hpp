// A local East/North/Up vector in metres: how noise and local positions are expressed.
#pragma once

namespace gpsemu {

struct Enu {
  double east_m = 0.0;
  double north_m = 0.0;
  double up_m = 0.0;
};

inline Enu operator+(const Enu& a, const Enu& b) {
  return {a.east_m + b.east_m, a.north_m + b.north_m, a.up_m + b.up_m};
}
inline Enu operator-(const Enu& a, const Enu& b) {
  return {a.east_m - b.east_m, a.north_m - b.north_m, a.up_m - b.up_m};
}
inline Enu operator*(double k, const Enu& a) { return {k * a.east_m, k * a.north_m, k * a.up_m}; }

}  // namespace gpsemu
