// Satellite orbits from real data, computed by Debian's RTKLIB and wrapped once here: a RINEX 2/3
// navigation file (broadcast ephemerides: RTKLIB's readrnx and satpos, i.e. eph2pos/geph2pos/
// seph2pos) or the embedded default sky (a real merged multi-GNSS navigation file of the whole of
// 2026-03-09, GPS/GLONASS/Galileo/BeiDou/QZSS, plus GNSS two-line elements of 2020-12-01 for SBAS
// and the QZSS satellites the file lacks, through RTKLIB's tle_pos; data/sky/README.md, docs/sky.md). Also the geometry helpers the sky needs from RTKLIB: azimuth/elevation
// (satazel), single-clock DOP (dops) and the geoid (geoidh, its embedded EGM96 1x1 degree model).
// No RTKLIB type appears in this header. Times are GPS time in seconds since 1980-01-06.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "nmea/fix.hpp"

namespace gpsemu::sky {

/// A satellite by its system and the system's own number (GPS PRN, GLONASS slot, SBAS PRN ...).
struct SatelliteId {
  nmea::GnssSystem system = nmea::GnssSystem::gps;
  int sv_id = 0;
  friend bool operator==(const SatelliteId&, const SatelliteId&) = default;
};

/// Earth-centred, earth-fixed WGS84 coordinates (metres).
struct Ecef {
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
};

/// A satellite's position (metres) and velocity (metres per second), ECEF.
struct EcefMotion {
  Ecef position;
  double vx_mps = 0.0, vy_mps = 0.0, vz_mps = 0.0;
};

/// Seconds of GPS time since 1980-01-06T00:00:00 GPST.
using GpsSeconds = double;
inline constexpr double kSiderealDayS = 86164.0905;

class Orbits {
 public:
  /// Reads a RINEX 2 or 3 navigation file (GPS, GLONASS, Galileo, BeiDou, QZSS, SBAS records).
  /// Throws std::runtime_error naming the file when it cannot be read or has no ephemeris.
  [[nodiscard]] static std::shared_ptr<const Orbits> from_rinex_nav(const std::string& path);
  /// The embedded default sky (data/sky/, docs/sky.md). Throws std::runtime_error if RTKLIB
  /// cannot read it (never for a correct build).
  [[nodiscard]] static std::shared_ptr<const Orbits> embedded_default();

  ~Orbits();
  Orbits(const Orbits&) = delete;
  Orbits& operator=(const Orbits&) = delete;

  /// Satellites with an orbit in the data, sorted by system then number.
  [[nodiscard]] const std::vector<SatelliteId>& satellites() const;
  /// Position of satellites()[index] at `t` (already mapped by map_time); nullopt when the data
  /// has no valid orbit for it then (no ephemeris close enough in time, or unhealthy).
  [[nodiscard]] std::optional<Ecef> position(std::size_t index, GpsSeconds t) const;
  /// Position and velocity (RTKLIB's), for interpolating between positions far apart.
  [[nodiscard]] std::optional<EcefMotion> motion(std::size_t index, GpsSeconds t) const;
  /// The data's day [start, start + 1 day) in GPS seconds.
  [[nodiscard]] GpsSeconds coverage_start() const;
  /// `t` itself when the data covers it; otherwise the moment of the data's day at the same
  /// sidereal time (t - start modulo a sidereal day): the same orientation of the Earth under
  /// the satellites of that day, a plausible real geometry for any date.
  [[nodiscard]] GpsSeconds map_time(GpsSeconds t) const;
  /// What the data is ("RINEX navigation FILE", "embedded ...").
  [[nodiscard]] const std::string& description() const;

 private:
  struct Impl;
  static std::shared_ptr<const Orbits> read_embedded();
  explicit Orbits(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// Azimuth (degrees true, [0, 360)) and elevation (degrees, [-90, 90]) of a satellite.
struct AzEl {
  double azimuth_deg = 0.0;
  double elevation_deg = 0.0;
};
/// Receiver at `receiver_ecef` / geodetic (lat_deg, lon_deg, height above the ellipsoid in
/// metres): RTKLIB's geodist + satazel (no light-time or Sagnac correction is needed at degrees).
[[nodiscard]] AzEl azimuth_elevation(const std::array<double, 3>& receiver_geodetic_deg_deg_m,
                                     const Ecef& receiver, const Ecef& satellite);
/// WGS84 geodetic (degrees, degrees, ellipsoidal height in metres) to ECEF (RTKLIB's pos2ecef).
[[nodiscard]] Ecef to_ecef(double lat_deg, double lon_deg, double height_m);

/// Geoid height above the WGS84 ellipsoid (metres): RTKLIB's geoidh with its embedded EGM96
/// 1x1 degree model (present in Debian's build).
[[nodiscard]] double geoid_separation_m(double lat_deg, double lon_deg);

/// RTKLIB's dops(): GDOP, PDOP, HDOP, VDOP with ONE receiver clock (all systems share it),
/// satellites below `mask_deg` ignored; all zero with fewer than 4. For checking our own
/// multi-clock DOP (sky/dop.hpp) on one system.
struct RtklibDops {
  double gdop = 0.0, pdop = 0.0, hdop = 0.0, vdop = 0.0;
};
[[nodiscard]] RtklibDops rtklib_single_clock_dops(std::span<const AzEl> satellites, double mask_deg);

}  // namespace gpsemu::sky
