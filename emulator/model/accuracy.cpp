#include "emulator/model/accuracy.hpp"

#include <algorithm>
#include <cmath>

namespace gpsemu::sky {

AccuracyFloor accuracy_floor(nmea::FixQuality quality) {
  switch (quality) {
    case nmea::FixQuality::dgps: return {0.2, 0.3, 0.05};
    case nmea::FixQuality::rtk_float: return {0.05, 0.075, 0.02};
    case nmea::FixQuality::rtk_fixed: return {0.01, 0.015, 0.02};
    default: return {0.3, 0.45, 0.05};
  }
}

void apply_accuracy_floor(nmea::Fix& fix) {
  const AccuracyFloor f = accuracy_floor(fix.quality);
  fix.sigma_lat_m = std::max(fix.sigma_lat_m, f.axis_m);
  fix.sigma_lon_m = std::max(fix.sigma_lon_m, f.axis_m);
  fix.sigma_alt_m = std::max(fix.sigma_alt_m, f.vertical_m);
  fix.range_rms_m = std::max(fix.range_rms_m, f.axis_m);
  fix.sigma_speed_mps = std::max(fix.sigma_speed_mps, f.speed_mps);
}

double horizontal_accuracy_m(const nmea::Fix& fix) { return std::hypot(fix.sigma_lat_m, fix.sigma_lon_m); }

}  // namespace gpsemu::sky
