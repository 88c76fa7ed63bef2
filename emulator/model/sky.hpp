// The receiver's sky: the satellites of the systems its model tracks, where they are (azimuth,
// elevation from real orbits, sky/orbits.hpp), how strong (C/N0 by elevation), which are used
// (above the elevation mask, not obstructed, strong enough, within the channels) and the DOPs of
// the used ones (sky/dop.hpp). Computed once a GPS second (satellite positions from orbit nodes
// ten minutes apart, cubic Hermite interpolation of RTKLIB's positions and velocities) and
// interpolated between seconds. Deterministic; the only
// randomness (per-satellite C/N0 offsets, the cold-start acquisition order) comes from the seed.
// docs/sky.md.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "emulator/model/geo.hpp"
#include "emulator/model/sky/dop.hpp"
#include "emulator/model/sky/orbits.hpp"
#include "emulator/model/sky/tracking.hpp"
#include "emulator/model/time.hpp"
#include "nmea/fix.hpp"

namespace gpsemu {

/// An obstruction: between two azimuths (degrees true, clockwise from `from` to `to`) nothing
/// below `min_elevation_deg` is received (--sky-mask).
struct SkyMaskSector {
  double from_azimuth_deg = 0.0;
  double to_azimuth_deg = 360.0;
  double min_elevation_deg = 0.0;
};
/// "urban-canyon" (a north-south street between buildings: 10 degrees along the street, 45
/// across it), "open" (none), or sectors "FROM-TO:ELEV[,FROM-TO:ELEV...]" in degrees. Throws
/// std::invalid_argument naming the bad part.
[[nodiscard]] std::vector<SkyMaskSector> parse_sky_mask(std::string_view text);

struct SkyOptions {
  std::shared_ptr<const sky::Orbits> orbits;  ///< empty: the embedded default sky
  sky::Tracking tracking;               ///< systems, channels, mask, C/N0 threshold
  std::vector<SkyMaskSector> obstruction;     ///< --sky-mask
  std::optional<int> max_used;                ///< --satellites: at most this many used
  std::uint64_t seed = 1;
};

/// What the sky gave an epoch.
struct SkyState {
  int listed = 0;   ///< satellites written to fix.satellites
  int used = 0;     ///< of them used
  sky::Dops dops;   ///< of the used ones; all zero when they do not make a 3-D fix
};

class Sky {
 public:
  /// The receiver stands at `receiver` (latitude, longitude, height above the ellipsoid).
  Sky(const SkyOptions& options, const Geodetic& receiver_ellipsoidal);

  /// How the receiver is doing, for fill().
  struct Tracking {
    double acquired_fraction = 1.0;  ///< cold start: share of the satellites acquired so far (0..1)
    bool solving = true;             ///< false: none is used (no fix, no pose)
    int max_used = 64;               ///< a 2-D start uses 3
  };

  /// Writes the satellites at UTC `t` into fix.satellites (by system, then number; the highest
  /// first when more than nmea::max_satellites are tracked) and fix.satellites_in_view.
  SkyState fill(UtcNs t, const Tracking& tracking, nmea::Fix& fix);

  [[nodiscard]] const sky::Orbits& orbits() const { return *orbits_; }

 private:
  /// Where a satellite is seen at a whole GPS second. el < -90: no orbit then.
  struct Look {
    float az = 0.0f, el = -100.0f;
    sky::LineOfSight line;  // unit vector east-north-up
  };
  struct Entry {
    std::uint16_t sat = 0;           // index into tracked_
    float az0 = 0, el0 = 0, az1 = 0, el1 = 0;
    std::uint8_t cn0 = 0;
    bool usable = false;             // above the mask, strong enough
    bool fixed = false;              // its integer degrees stay the same all second (see fill)
    sky::LineOfSight line;           // at the second
  };
  void advance_to(std::int64_t second);
  /// Keeps at most `limit` of the usable entries used (a spread geometry).
  void select_used(int limit);
  [[nodiscard]] int clock_of(const Entry& e) const;
  void snapshot(std::int64_t second, std::vector<Look>& looks);
  [[nodiscard]] std::optional<sky::Ecef> position(std::size_t k, double mapped_t);
  [[nodiscard]] bool obstructed(double az_deg, double el_deg) const;
  void write_entry(const Entry& e, float f, nmea::SatelliteInView& out) const;

  std::shared_ptr<const sky::Orbits> orbits_;
  SkyOptions options_;
  sky::Ecef receiver_ecef_;
  std::array<double, 3> east_{}, north_{}, up_{};  // the receiver's local axes (ECEF unit vectors)
  std::vector<std::size_t> tracked_;            // satellites of the tracked systems
  std::vector<float> cn0_offset_db_;            // per satellite of the orbits
  std::vector<float> acquisition_rank_;         // per satellite: 0..1, seeded
  // Orbit nodes: position and velocity every kNodeS seconds of mapped time, the two around the
  // time asked (cubic Hermite between them).
  std::int64_t node_base_ = INT64_MIN;
  std::vector<std::array<std::optional<sky::EcefMotion>, 2>> nodes_;
  std::int64_t second_ = INT64_MIN;             // the GPS second of looks 0 (looks 1: second + 1)
  double last_mapped_ = 0.0;                    // the mapped time of the last snapshot
  std::vector<Look> look0_, look1_;             // per tracked satellite
  std::vector<std::int64_t> hidden_until_;      // per tracked: below the horizon before this second
  std::vector<Entry> entries_;                  // listed this second, by system then number
  std::vector<nmea::SatelliteInView> written_;  // entries_ as written at any moment of the second
  std::vector<std::uint8_t> moving_;            // entries_ whose integer degrees change within it
  sky::Dops dops_;
  int used_ = 0;
  Tracking tracking_{};
};

/// GPS seconds (since 1980-01-06) of a UTC time (18 leap seconds, as since 2017).
[[nodiscard]] double gps_seconds_of(UtcNs t);

}  // namespace gpsemu
