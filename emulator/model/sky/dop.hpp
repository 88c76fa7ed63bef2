// Dilution of precision from the geometry of the satellites used, with one receiver clock per
// system (GPS, QZSS and SBAS share GPS time; GLONASS, Galileo and BeiDou each have their own
// clock unknown): G = [-e_east, -e_north, -e_up, 1 in the column of the satellite's clock],
// Q = (G^T G)^-1. RTKLIB's dops() has a single clock, so this is computed here (a few lines of
// linear algebra) and checked against RTKLIB on one system (tests/unit/model/sky_test.cpp).
#pragma once

#include <span>

#include "nmea/fix.hpp"

namespace gpsemu::sky {

struct Dops {
  double gdop = 0.0, pdop = 0.0, hdop = 0.0, vdop = 0.0, tdop = 0.0;  ///< TDOP of the first clock
  [[nodiscard]] bool valid() const { return pdop > 0.0; }
};

struct UsedSatellite {
  double azimuth_deg = 0.0;
  double elevation_deg = 0.0;
  nmea::GnssSystem system = nmea::GnssSystem::gps;
};

/// The unit vector from the receiver to a satellite in the receiver's east-north-up frame
/// (east = cos(el) sin(az), north = cos(el) cos(az), up = sin(el)).
struct LineOfSight {
  double east = 0.0, north = 0.0, up = 0.0;
  nmea::GnssSystem system = nmea::GnssSystem::gps;
};

/// All zero when the geometry does not determine position and clocks (fewer satellites than
/// 3 + clocks, or a singular matrix).
[[nodiscard]] Dops multi_clock_dops(std::span<const UsedSatellite> used);
/// The same from the lines of sight (no trigonometry: what the sky computes once a second).
[[nodiscard]] Dops multi_clock_dops(std::span<const LineOfSight> used);

}  // namespace gpsemu::sky
