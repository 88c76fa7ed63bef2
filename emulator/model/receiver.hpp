// The receiver model: truth at an epoch + noise -> the Fix a receiver would report (position in
// WGS84 via GeographicLib, MSL altitude with geoid separation, speed/course, satellites, DOP,
// GST error estimates), and the receiver's states: cold start (acquisition, then 2-D, then 3-D),
// scheduled outages (tunnels), fix quality (gps, dgps, RTK float/fixed) with correspondingly
// smaller noise. Pure and deterministic given the seeds.
//
// How satellites, HDOP and GST relate to the noise (documented in the README section too):
//   sigma_h = hypot(sigma_east, sigma_north) of the noise model's output (estimate_noise_sigma_m)
//   HDOP    = sigma_h / kUereM, clamped to [kMinDerivedHdop, kMaxDerivedHdop]   (unless --hdop)
//   used    = round((kHdopSqrtSatellites / HDOP)^2), clamped to [5, 16]          (unless --satellites)
//   in view = min(32, used + 2 + used / 4);   VDOP = 1.5 HDOP;   PDOP = hypot(HDOP, VDOP)
//   GST: sigma lat/lon/alt = scale x sigma north/east/up; rms = scale x sigma_h / HDOP
// where scale = noise_scale(quality): DOPs describe the geometry and do not change with the fix
// quality; the corrections (DGPS, RTK) shrink the range errors, hence the position noise.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "emulator/model/enu.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/sky.hpp"
#include "emulator/sources/pose_source.hpp"
#include "emulator/model/time.hpp"
#include "nmea/fix.hpp"

namespace gpsemu {

/// User equivalent range error of an autonomous fix in the HDOP relation above (metres).
inline constexpr double kUereM = 0.4;
inline constexpr double kMinDerivedHdop = 0.5;
inline constexpr double kMaxDerivedHdop = 20.0;
/// HDOP ~ kHdopSqrtSatellites / sqrt(satellites used): 12 satellites give 0.87, 8 give 1.06.
inline constexpr double kHdopSqrtSatellites = 3.0;
inline constexpr int kMinDerivedSatellites = 5;
inline constexpr int kMaxDerivedSatellites = 16;
/// Satellites used in the 2-D phase of a cold start.
inline constexpr int kTwoDSatellites = 3;

/// How much a fix quality shrinks the noise model's output (typical horizontal accuracy relative
/// to an autonomous fix): gps 1, dgps (SBAS/DGPS, metre level) 0.4, rtk_float (decimetres) 0.1,
/// rtk_fixed (centimetres) 0.01; the others 1.
[[nodiscard]] double noise_scale(nmea::FixQuality quality);

/// A scheduled loss of every satellite (tunnel, underpass), in seconds after the first epoch.
struct Outage {
  double start_s = 0.0;     ///< start (seconds after the first epoch), >= 0
  double duration_s = 0.0;  ///< length (seconds), > 0
};

struct ReceiverOptions {
  double geoid_sep_m = 0.0;   ///< geoid separation written in GGA (metres); altitudes are MSL
  std::optional<int> satellites_used;  ///< satellites used in a 3-D fix; empty: derived from HDOP
  std::optional<double> hdop;          ///< HDOP of a 3-D fix; empty: derived from noise_sigma_m
  /// 1-sigma (RMS) error per axis of the noise model's output before the quality scale (metres);
  /// the pipeline sets it with estimate_noise_sigma_m (receiver_config.hpp).
  Enu noise_sigma_m{};
  nmea::FixQuality quality = nmea::FixQuality::gps;  ///< quality reported with a fix
  double cold_start_s = 0.0;     ///< no fix for this long after the first epoch (seconds)
  double cold_start_2d_s = 0.0;  ///< then a 2-D fix for this long (seconds)
  std::vector<Outage> outages;   ///< no satellites, no fix, during each
  std::uint64_t sky_seed = 1;    ///< seed of the satellite sky (the run's --seed)
  double course_min_speed_mps = 0.05;  ///< below this speed the last course is held
  /// Fill each satellite's PRN, elevation, azimuth and SNR (GSA, GSV). When false (no sentence of
  /// the set lists satellites) only the counts are meaningful: fix.satellites_in_view and which
  /// entries are `used`; the sky's per-satellite trigonometry, most of an epoch's cost, is skipped.
  bool satellite_details = true;
};

/// The satellite geometry a receiver reports with a 3-D fix (see the relations above).
struct Geometry {
  int satellites_used = 0;
  int satellites_in_view = 0;
  double hdop = 0.0, vdop = 0.0, pdop = 0.0;
};
[[nodiscard]] Geometry resolve_geometry(const ReceiverOptions& options);

/// RMS per axis of `config`'s noise model (seeded with `seed`) sampled at 1 Hz over 3 hours
/// (metres). Model-agnostic; takes milliseconds. Throws like make_noise_model.
[[nodiscard]] Enu estimate_noise_sigma_m(const noise::NoiseConfig& config, std::uint64_t seed);

/// What the receiver is doing at a moment.
enum class ReceiverPhase {
  outage,     ///< no satellites (scheduled outage): empty GSV, no fix
  acquiring,  ///< cold start: satellites appearing one by one, no fix
  two_d,      ///< cold start: 2-D fix with kTwoDSatellites satellites
  three_d,    ///< normal operation
};
[[nodiscard]] ReceiverPhase phase_at(const ReceiverOptions& options, double since_start_s);

class Receiver {
 public:
  Receiver(const LocalFrame& frame, const ReceiverOptions& options,
           std::unique_ptr<noise::NoiseModel> noise, UtcNs first_epoch);

  /// The fix for epoch `t`; no fix when `truth` is empty (satellites still tracked, none used) or
  /// during an outage or the acquisition phase of a cold start. Call with non-decreasing `t`.
  [[nodiscard]] nmea::Fix fix_at(UtcNs t, const std::optional<sources::Truth>& truth);

  /// Starts again at `t` (a cold start, CFG-RST): the cold-start phases and outages of the
  /// options count from `t`, the held course is forgotten.
  void restart(UtcNs t) {
    first_epoch_ = t;
    last_course_deg_.reset();
  }

  [[nodiscard]] const Geometry& geometry() const { return geometry_; }

 private:
  const LocalFrame& frame_;
  ReceiverOptions options_;
  std::unique_ptr<noise::NoiseModel> noise_;
  UtcNs first_epoch_;
  Geometry geometry_;
  Sky sky_;
  double noise_sigma_h_m_;  ///< hypot(east, north) of options_.noise_sigma_m (metres)
  std::optional<double> last_course_deg_;
};

}  // namespace gpsemu
