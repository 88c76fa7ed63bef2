// Test support for the NMEA tests: readable expected values — a UTC time from its calendar fields,
// degrees from degrees and decimal minutes, metres per second in a knot.
#pragma once

#include <chrono>

#include "nmea/fix.hpp"

namespace gpsemu::test {

/// The UTC instant y-mo-d h:mi:s.ms.
inline nmea::UtcTime utc(int y, unsigned mo, unsigned d, int h, int mi, int s, int ms = 0) {
  using namespace std::chrono;
  return nmea::UtcTime{sys_days{year{y} / month{mo} / day{d}}} + hours{h} + minutes{mi} + seconds{s} +
         milliseconds{ms};
}

/// Degrees from degrees and decimal minutes, for readable expectations.
constexpr double dm(double degrees, double minutes) { return degrees + minutes / 60.0; }

constexpr double mps_per_knot = 1852.0 / 3600.0;

}  // namespace gpsemu::test
