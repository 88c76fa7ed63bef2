// The receiver model: truth at an epoch + noise -> the Fix a receiver would report (position in
// WGS84 via GeographicLib, MSL altitude with geoid separation, speed/course, satellites, DOP,
// GST error estimates), and the receiver's states: cold start (acquisition, then 2-D, then 3-D),
// scheduled outages (tunnels), fix quality (gps, dgps, RTK float/fixed) with correspondingly
// smaller noise. Pure and deterministic given the seeds.
//
// How satellites, DOP and the accuracy relate (docs/sky.md, docs/noise-and-calibration.md):
//   the sky (sky.hpp) gives the satellites of the model's systems from real orbits; used = above
//   the elevation mask, not obstructed, C/N0 over the threshold, within the channels; DOPs from
//   the used ones' geometry (one clock per system)
//   the emulated error is the noise model's, x scale; with noise_scales_with_dop also x HDOP /
//   kReferenceHdop horizontally and x VDOP / kReferenceVdop vertically
//   reported accuracy: the error actually applied, per axis: the noise model's 1-sigma
//   (noise_sigma_m) x the same scales x accuracy_ratio (1: honest; a calibrated receiver's own
//   reported/actual ratio), never below the quality's floor (sky::apply_accuracy_floor). Without noise
//   (--noise none) a receiver still claims what its geometry gives: sigma_h = HDOP x UERE x scale,
//   sigma_v = VDOP x UERE x scale. GST's RMS of the ranges is UERE x scale.
// where scale = noise_scale(quality) / noise_scale(noise_quality) (the noise parameters describe the
// receiver at noise_quality: a calibrated RTK rover's are centimetres at rtk-fixed) and UERE the
// model's (the receiver table's tracking) unless uere_m is set (calibrate writes it: the log's sigma / its median HDOP).
#pragma once

#include <cstdint>
#include <string>
#include <memory>
#include <optional>
#include <vector>

#include "emulator/model/enu.hpp"
#include "emulator/model/epoch.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/geo_near.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/noise/rng.hpp"
#include "emulator/model/noise/velocity_noise.hpp"
#include "emulator/model/sky.hpp"
#include "emulator/model/receiver_models.hpp"
#include "emulator/model/static_hold.hpp"
#include "emulator/sources/pose_source.hpp"
#include "emulator/model/time.hpp"
#include "nmea/fix.hpp"
#include "nmea/line_budget.hpp"

namespace gpsemu {

/// The range error per unit of HDOP that `gpsemu judge` assumes for a logged receiver that states only
/// its HDOP (metres): its filter's measurement sigma is median HDOP x this / sqrt 2.
inline constexpr double kUereM = 0.4;
/// The geometry at which the emulated error equals the noise model's (noise_scales_with_dop).
inline constexpr double kReferenceHdop = 1.0;
inline constexpr double kReferenceVdop = 1.5;
/// Satellites used in the 2-D phase of a cold start.
inline constexpr int kTwoDSatellites = 3;

/// How much a fix quality shrinks the noise model's output (typical horizontal accuracy relative
/// to an autonomous fix): gps 1, dgps (SBAS/DGPS, metre level) 0.4, rtk_float (decimetres) 0.1,
/// rtk_fixed (centimetres) 0.01; the others 1.
[[nodiscard]] double noise_scale(nmea::FixQuality quality);
/// The factor the noise model's output is multiplied by at `quality` when its parameters describe
/// the receiver at `noise_quality`: noise_scale(quality) / noise_scale(noise_quality).
[[nodiscard]] double noise_scale(nmea::FixQuality quality, nmea::FixQuality noise_quality);

/// A scheduled loss of every satellite (tunnel, underpass), in seconds after the first epoch.
struct Outage {
  double start_s = 0.0;     ///< start (seconds after the first epoch), >= 0
  double duration_s = 0.0;  ///< length (seconds), > 0
};

/// What a receiver reports as its course over ground while slower than course_min_speed_mps.
enum class CourseAtRest {
  empty,     ///< none (RMC/VTG course empty, NAV-PVT headMot frozen): u-blox, below 0.4 m/s in its logs
  held,      ///< the last course (SiRF, SkyTraq, Quectel: with the speed clamped to 0)
  measured,  ///< the course of the measured velocity, whatever its speed (an RTK receiver's raw NMEA)
};
/// "empty", "held", "measured"; throws std::invalid_argument listing them.
[[nodiscard]] CourseAtRest parse_course_at_rest(const std::string& text);

struct ReceiverOptions {
  /// Geoid separation written in GGA (metres); empty: the EGM96 geoid at the origin (RTKLIB
  /// geoidh). Altitudes are MSL either way.
  std::optional<double> geoid_sep_m;
  std::optional<int> satellites_used;  ///< --satellites: at most this many used
  std::optional<double> hdop;          ///< --hdop: report this HDOP (VDOP, PDOP scaled alike)
  /// 1-sigma (RMS) error per axis of the noise model's output before the quality scale (metres);
  /// the pipeline sets it with estimate_noise_sigma_m (receiver_config.hpp).
  Enu noise_sigma_m{};
  nmea::FixQuality quality = nmea::FixQuality::gps;  ///< quality reported with a fix
  /// The quality the noise parameters were measured at (--noise-quality): the noise is scaled by
  /// noise_scale(quality) / noise_scale(noise_quality).
  nmea::FixQuality noise_quality = nmea::FixQuality::gps;
  /// Reported accuracy / the error actually applied (--accuracy-ratio, 0.01..10): real receivers are
  /// often optimistic (< 1); calibrate measures it from a log that reports its accuracy (GST).
  double accuracy_ratio = 1.0;
  double cold_start_s = 0.0;     ///< no fix for this long after the first epoch (seconds)
  double cold_start_2d_s = 0.0;  ///< then a 2-D fix for this long (seconds)
  std::vector<Outage> outages;   ///< no satellites, no fix, during each
  std::uint64_t sky_seed = 1;    ///< seed of the satellite sky (the run's --seed)
  double course_min_speed_mps = 0.4;  ///< below this speed the course is course_at_rest's
  CourseAtRest course_at_rest = CourseAtRest::empty;  ///< --course-at-rest
  /// 1-sigma white noise on the reported heading (degrees, --heading-noise), 0..180: a dual-antenna
  /// receiver's heading (HDT, THS) from the truth's yaw_deg.
  double heading_sigma_deg = 0.2;
  /// Kept for the pipeline's settings; the sky is always computed (its counts and DOPs are needed).
  bool satellite_details = true;
  /// The receiver model's sky: systems, channels, mask, C/N0 threshold, UERE (the receiver table's, facts_of(model).tracking).
  sky::Tracking tracking = facts_of(ReceiverModel::generic).tracking;
  std::optional<double> elevation_mask_deg;  ///< --elevation-mask; empty: the model's
  std::vector<SkyMaskSector> sky_mask;       ///< --sky-mask
  std::optional<double> uere_m;              ///< UERE of an autonomous fix (metres); empty: the model's
  bool noise_scales_with_dop = false;        ///< --noise-scales-with-dop
  std::shared_ptr<const sky::Orbits> orbits; ///< --ephemeris; empty: the embedded default sky
  StaticHoldOptions hold;                    ///< --hold-radius, --hold-speed (static_hold.hpp); off by default
  /// The reported velocity's error (--velocity-noise, --velocity-wander, --velocity-wander-tau,
  /// --velocity-static-clamp; noise/velocity_noise.hpp); both sigmas 0: the truth's velocity.
  noise::VelocityNoiseParams velocity;
};

/// The most satellites a receiver lists and uses (the line budget's worst case) and a typical DOP.
struct Geometry {
  int satellites_used = 0;
  int satellites_in_view = 0;
  /// The model's most satellites in view by system (GSV groups, GSA per system): what the widest
  /// epoch is sized on (resolve_geometry's worst case, also in a receiver's first-epoch geometry).
  std::vector<nmea::SystemSatellites> in_view_by_system;
  double hdop = 0.0, vdop = 0.0, pdop = 0.0;
};
/// Worst case of the model's systems: GPS 14, GLONASS 12, Galileo 12, BeiDou 18, QZSS 5, SBAS 4
/// in view at once (twice for a dual-band model's GSV), capped at nmea::max_satellites.
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

  /// Epoch `t` as the model knows it, the first stage of the epoch (model/epoch.hpp): its fix (none
  /// when `truth` is empty, satellites still tracked and none used, or during an outage or the
  /// acquisition phase of a cold start), a clean front end, no relative position. Made in place,
  /// once (a 2 KB value). Call with non-decreasing `t`.
  [[nodiscard]] ReceiverEpoch epoch_at(UtcNs t, const std::optional<sources::Truth>& truth);
  /// epoch_at(t, truth).fix.
  [[nodiscard]] nmea::Fix fix_at(UtcNs t, const std::optional<sources::Truth>& truth) { return epoch_at(t, truth).fix; }

  /// Starts again at `t` (a cold start, CFG-RST): the cold-start phases and outages of the
  /// options count from `t`, the held course is forgotten.
  void restart(UtcNs t) { restart(t, configured_cold_start_s_); }
  /// The same with a cold start of `cold_start_s` (a reset fault's boot and TTFF) in place of
  /// the options' (--cold-start); the 2-D phase of the options follows it.
  void restart(UtcNs t, double cold_start_s) {
    first_epoch_ = t;
    options_.cold_start_s = cold_start_s;
    last_course_deg_.reset();
    hold_.reset();
    velocity_noise_.reset();
  }

  /// The geometry at the first epoch: satellites listed and used, DOPs.
  [[nodiscard]] const Geometry& geometry() const { return geometry_; }

 private:
  const LocalFrame& frame_;
  ReceiverOptions options_;
  std::unique_ptr<noise::NoiseModel> noise_;
  UtcNs first_epoch_;
  Sky sky_;
  Geometry geometry_;
  double geoid_sep_m_;
  double uere_m_;
  std::optional<double> last_course_deg_;
  double configured_cold_start_s_ = 0.0;  ///< the options' (--cold-start)
  noise::Rng heading_rng_;  ///< the heading's noise, its own stream of the run's seed
  StaticHold hold_;
  noise::VelocityNoise velocity_noise_;  ///< the velocity's error, its own stream of the run's seed
  NearGeodetic near_;  ///< the reported positions about the last one converted exactly
};

}  // namespace gpsemu
