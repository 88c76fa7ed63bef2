// Independent computations the sky tests compare RTKLIB and the sky with: IS-GPS-200's
// ephemeris algorithm for a GPS record (written here from the specification) and azimuth/elevation
// by GeographicLib. Shared by sky_test.cpp and sky_records_test.cpp.
#pragma once

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <cmath>
#include <numbers>

#include "emulator/model/geo.hpp"
#include "emulator/model/sky/orbits.hpp"

namespace gpsemu::sky_test_support {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDeg = kPi / 180.0;
inline constexpr double kMu = 3.986005e14;          // WGS84 GM of IS-GPS-200 (m^3/s^2)
inline constexpr double kOmegaE = 7.2921151467e-5;  // earth rotation (rad/s)
inline const Geodetic kMadison{43.0725, -89.4125, 260.0 - 33.9};  // ellipsoidal height

inline double distance_m(const sky::Ecef& a, const sky::Ecef& b) {
  return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m, a.z_m - b.z_m);
}

inline sky::AzEl azel_by_geographiclib(const Geodetic& rx, const sky::Ecef& sat) {
  const GeographicLib::LocalCartesian frame(rx.lat_deg, rx.lon_deg, rx.alt_m);
  double e = 0, n = 0, u = 0;
  // LocalCartesian::Forward takes geodetic; go through the Geocentric inverse.
  double lat = 0, lon = 0, h = 0;
  GeographicLib::Geocentric::WGS84().Reverse(sat.x_m, sat.y_m, sat.z_m, lat, lon, h);
  frame.Forward(lat, lon, h, e, n, u);
  double az = std::atan2(e, n) / kDeg;
  if (az < 0) az += 360.0;
  return {az, std::atan2(u, std::hypot(e, n)) / kDeg};
}

/// A GPS broadcast ephemeris (RINEX 3 fields; toe in seconds of the GPS week).
struct Kepler {
  double af0 = 1.0e-5, af1 = 1.0e-12, af2 = 0.0;
  double iode = 42, crs = 35.5, dn = 4.5e-9, m0 = 0.3;
  double cuc = 1.8e-6, e = 0.0105, cus = 8.2e-6, sqrt_a = 5153.65;
  double toe = 180000.0, cic = -1.1e-7, omega0 = 1.0, cis = 9.0e-8;
  double i0 = 0.958, crc = 210.3, w = 0.52, omega_dot = -8.1e-9;
  double idot = 1.2e-10, week = 2134;
};

inline sky::Ecef is_gps_200(const Kepler& k, double tk) {
  const double a = k.sqrt_a * k.sqrt_a;
  const double n = std::sqrt(kMu / (a * a * a)) + k.dn;
  const double m = k.m0 + n * tk;
  double ecc_anomaly = m;
  for (int i = 0; i < 30; ++i) ecc_anomaly = m + k.e * std::sin(ecc_anomaly);
  const double nu = std::atan2(std::sqrt(1 - k.e * k.e) * std::sin(ecc_anomaly), std::cos(ecc_anomaly) - k.e);
  const double phi = nu + k.w;
  const double s2 = std::sin(2 * phi), c2 = std::cos(2 * phi);
  const double u = phi + k.cus * s2 + k.cuc * c2;
  const double r = a * (1 - k.e * std::cos(ecc_anomaly)) + k.crs * s2 + k.crc * c2;
  const double inc = k.i0 + k.cis * s2 + k.cic * c2 + k.idot * tk;
  const double omega = k.omega0 + (k.omega_dot - kOmegaE) * tk - kOmegaE * k.toe;
  const double xp = r * std::cos(u), yp = r * std::sin(u);
  return {xp * std::cos(omega) - yp * std::cos(inc) * std::sin(omega), xp * std::sin(omega) + yp * std::cos(inc) * std::cos(omega),
          yp * std::sin(inc)};
}

}  // namespace gpsemu::sky_test_support
