#include "emulator/model/receiver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "emulator/model/accuracy.hpp"

namespace gpsemu {
namespace {

constexpr double kSigmaSampleRateHz = 1.0;
constexpr int kSigmaSamples = 3 * 3600;
/// The heading noise's random stream ("HDNG"): apart from the noise models' streams.
constexpr std::uint64_t kHeadingNoiseStream = 0x48444E47;

SkyOptions sky_options(const ReceiverOptions& o) {
  SkyOptions s;
  s.orbits = o.orbits;
  s.tracking = o.tracking;
  if (o.elevation_mask_deg) s.tracking.elevation_mask_deg = *o.elevation_mask_deg;
  s.obstruction = o.sky_mask;
  s.max_used = o.satellites_used;
  s.seed = o.sky_seed;
  return s;
}

double geoid_at(const LocalFrame& frame, const ReceiverOptions& o) {
  return o.geoid_sep_m ? *o.geoid_sep_m : sky::geoid_separation_m(frame.origin().lat_deg, frame.origin().lon_deg);
}

Geodetic ellipsoidal(const Geodetic& msl, double geoid_sep_m) { return {msl.lat_deg, msl.lon_deg, msl.alt_m + geoid_sep_m}; }

}  // namespace

double noise_scale(nmea::FixQuality quality) {
  switch (quality) {
    case nmea::FixQuality::dgps: return 0.4;
    case nmea::FixQuality::rtk_float: return 0.1;
    case nmea::FixQuality::rtk_fixed: return 0.01;
    default: return 1.0;
  }
}

double noise_scale(nmea::FixQuality quality, nmea::FixQuality noise_quality) {
  return noise_scale(quality) / noise_scale(noise_quality);
}

Geometry resolve_geometry(const ReceiverOptions& options) {
  using S = nmea::GnssSystem;
  const sky::SystemSet& sys = options.tracking.systems;
  Geometry g;
  int n = 0;
  for (const auto& [system, most] : {std::pair{S::gps, 14}, std::pair{S::glonass, 12}, std::pair{S::galileo, 12},
                                    std::pair{S::beidou, 18}, std::pair{S::qzss, 5}, std::pair{S::sbas, 4}}) {
    if (!sys.contains(system)) continue;
    const int in_view = options.tracking.dual_band ? 2 * most : most;
    g.in_view_by_system.push_back({system, in_view});
    n += in_view;
  }
  g.satellites_in_view = std::min(n, static_cast<int>(nmea::max_satellites));
  g.satellites_used = options.satellites_used ? std::min(*options.satellites_used, g.satellites_in_view) : g.satellites_in_view;
  g.hdop = options.hdop.value_or(1.0);
  g.vdop = 1.5 * g.hdop;
  g.pdop = std::hypot(g.hdop, g.vdop);
  return g;
}

Enu estimate_noise_sigma_m(const noise::NoiseConfig& config, std::uint64_t seed) {
  const auto model = noise::make_noise_model(config, seed);
  double se = 0.0, sn = 0.0, su = 0.0;
  for (int k = 0; k < kSigmaSamples; ++k) {
    const auto t = std::chrono::nanoseconds{std::llround(k * 1e9 / kSigmaSampleRateHz)};
    const Enu e = model->offset_at(t);
    se += e.east_m * e.east_m;
    sn += e.north_m * e.north_m;
    su += e.up_m * e.up_m;
  }
  return {std::sqrt(se / kSigmaSamples), std::sqrt(sn / kSigmaSamples), std::sqrt(su / kSigmaSamples)};
}

ReceiverPhase phase_at(const ReceiverOptions& options, double since_start_s) {
  for (const Outage& o : options.outages) {
    if (since_start_s >= o.start_s && since_start_s < o.start_s + o.duration_s) return ReceiverPhase::outage;
  }
  if (since_start_s < options.cold_start_s) return ReceiverPhase::acquiring;
  if (since_start_s < options.cold_start_s + options.cold_start_2d_s) return ReceiverPhase::two_d;
  return ReceiverPhase::three_d;
}

Receiver::Receiver(const LocalFrame& frame, const ReceiverOptions& options,
                   std::unique_ptr<noise::NoiseModel> noise, UtcNs first_epoch)
    : frame_(frame),
      options_(options),
      noise_(std::move(noise)),
      first_epoch_(first_epoch),
      sky_(sky_options(options), ellipsoidal(frame.origin(), geoid_at(frame, options))),
      geoid_sep_m_(geoid_at(frame, options)),
      uere_m_(options.uere_m.value_or(options.tracking.uere_m)),
      configured_cold_start_s_(options.cold_start_s),
      heading_rng_(options.sky_seed, kHeadingNoiseStream),
      hold_(options.hold),
      velocity_noise_(options.velocity, options.sky_seed) {
  nmea::Fix scratch;
  const SkyState s = sky_.fill(first_epoch, {}, scratch);
  geometry_.satellites_in_view = s.listed;
  geometry_.satellites_used = s.used;
  geometry_.hdop = s.dops.hdop;
  geometry_.vdop = s.dops.vdop;
  geometry_.pdop = s.dops.pdop;
  // The widest epoch is sized on the model's worst case by system, not on this first sky: the
  // satellites that rise later are in it.
  geometry_.in_view_by_system = resolve_geometry(options).in_view_by_system;
}

CourseAtRest parse_course_at_rest(const std::string& text) {
  if (text == "empty") return CourseAtRest::empty;
  if (text == "held") return CourseAtRest::held;
  if (text == "measured") return CourseAtRest::measured;
  throw std::invalid_argument("expected empty, held or measured, got '" + text + "'");
}

ReceiverEpoch Receiver::epoch_at(UtcNs t, const std::optional<sources::Truth>& truth) {
  ReceiverEpoch epoch;
  nmea::Fix& fix = epoch.fix;
  fix.time_utc = std::chrono::floor<std::chrono::milliseconds>(t);
  // The noise process runs whether or not there is a fix, so a fix that returns after an outage
  // continues the same smooth wander instead of restarting it.
  const auto since = t - first_epoch_;
  const Enu raw_error = noise_->offset_at(since);
  const double since_s = std::chrono::duration<double>(since).count();
  const ReceiverPhase phase = phase_at(options_, since_s);
  if (phase == ReceiverPhase::outage) {  // nothing in view
    hold_.reset();
    return epoch;
  }

  Sky::Tracking tracking;
  if (phase == ReceiverPhase::acquiring) tracking.acquired_fraction = since_s / options_.cold_start_s;
  const bool two_d = phase == ReceiverPhase::two_d;
  tracking.solving = truth && (two_d || phase == ReceiverPhase::three_d);
  if (two_d) tracking.max_used = kTwoDSatellites;
  const SkyState sky = sky_.fill(t, tracking, fix);
  // A cold receiver learns the time from its first satellite.
  if (phase == ReceiverPhase::acquiring) fix.time_valid = sky.listed > 0;
  if (!tracking.solving) {
    hold_.reset();
    return epoch;
  }
  // A 3-D fix needs the geometry to determine position and clocks; a 2-D start holds the height.
  if (!two_d && !sky.dops.valid()) return epoch;
  if (two_d && sky.used < kTwoDSatellites) return epoch;

  double hdop = sky.dops.valid() ? sky.dops.hdop : 0.0, vdop = sky.dops.vdop, pdop = sky.dops.pdop;
  if (two_d) {
    // Three satellites and the held height: a poor horizontal geometry.
    hdop = std::max(hdop, 2.5);
    vdop = 1.5 * hdop;
    pdop = std::hypot(hdop, vdop);
  }
  if (options_.hdop && !two_d) {
    const double k = *options_.hdop / std::max(hdop, 1e-9);
    hdop *= k;
    vdop *= k;
    pdop *= k;
  }
  const double scale = noise_scale(options_.quality, options_.noise_quality);
  double h_scale = scale, v_scale = scale;
  if (options_.noise_scales_with_dop) {
    h_scale *= hdop / kReferenceHdop;
    v_scale *= vdop / kReferenceVdop;
  }
  const Enu error{h_scale * raw_error.east_m, h_scale * raw_error.north_m, v_scale * raw_error.up_m};

  // The velocity, measured apart from the position (Doppler): the truth's plus its own error;
  // a chipset that clamps reports 0 below its threshold.
  double ve = truth->velocity_mps.east_m;
  double vn = truth->velocity_mps.north_m;
  double vu = truth->velocity_mps.up_m;
  const noise::VelocityNoiseParams& vp = options_.velocity;
  if (!vp.off()) {
    const Enu v_error = velocity_noise_.error_at(since);
    ve += v_error.east_m;
    vn += v_error.north_m;
    vu += v_error.up_m;
  }
  double speed_mps = std::sqrt(ve * ve + vn * vn);  // std::hypot's care for overflow costs 20 ns an epoch
  if (speed_mps < vp.static_clamp_mps) ve = vn = vu = speed_mps = 0.0;
  // Static hold: the last reported position repeats while slow and within the radius (slow in
  // 3-D, as the receiver measures it: a copter climbing in place is not standing still).
  const Enu reported_m = hold_.apply(truth->position_m + error, std::sqrt(speed_mps * speed_mps + vu * vu));
  if (hold_.holding()) ve = vn = vu = speed_mps = 0.0;  // holding, it reports no motion
  const Geodetic position = near_.to_geodetic(frame_, reported_m);
  fix.quality = options_.quality;
  fix.dimension = two_d ? nmea::FixDimension::two_d : nmea::FixDimension::three_d;
  fix.lat_deg = position.lat_deg;
  fix.lon_deg = position.lon_deg;
  fix.alt_msl_m = position.alt_m;
  fix.geoid_sep_m = geoid_sep_m_;
  fix.speed_mps = speed_mps;
  fix.vel_up_mps = vu;
  const bool moving = fix.speed_mps >= options_.course_min_speed_mps;
  if (moving || (options_.course_at_rest == CourseAtRest::measured && fix.speed_mps > 0.0)) {
    double course = std::atan2(ve, vn) * 180.0 / std::numbers::pi;
    if (course < 0.0) course += 360.0;
    last_course_deg_ = course;
  }
  if (moving || options_.course_at_rest != CourseAtRest::empty) fix.course_deg_true = last_course_deg_;
  if (truth->yaw_deg) {
    const double heading = *truth->yaw_deg + options_.heading_sigma_deg * heading_rng_.normal();
    fix.heading_deg_true = heading - 360.0 * std::floor(heading / 360.0);
  }
  fix.satellites_used = sky.used;
  fix.hdop = hdop;
  fix.vdop = vdop;
  fix.pdop = pdop;
  fix.tdop = sky.dops.tdop;
  fix.gdop = std::sqrt(pdop * pdop + fix.tdop * fix.tdop);
  // Reported accuracy: the error applied (the model's sigma x the scales x the receiver's ratio),
  // or without noise DOP x UERE x scale; never below the quality's floor (applied here, once).
  const Enu& sigma = options_.noise_sigma_m;
  const double k = options_.accuracy_ratio;
  if (sigma.east_m > 0.0 || sigma.north_m > 0.0 || sigma.up_m > 0.0) {
    fix.sigma_lat_m = k * h_scale * sigma.north_m;
    fix.sigma_lon_m = k * h_scale * sigma.east_m;
    fix.sigma_alt_m = k * v_scale * sigma.up_m;
  } else {
    fix.sigma_lat_m = hdop * uere_m_ * scale / std::numbers::sqrt2;
    fix.sigma_lon_m = fix.sigma_lat_m;
    fix.sigma_alt_m = vdop * uere_m_ * scale;
  }
  fix.range_rms_m = uere_m_ * scale;
  // The speed's accuracy: the velocity error's, over both horizontal axes (as hAcc is over both
  // position axes), times the receiver's own ratio; its floor below.
  fix.sigma_speed_mps = k * std::numbers::sqrt2 * vp.horizontal_sigma_mps();
  sky::apply_accuracy_floor(fix);
  return epoch;
}

}  // namespace gpsemu
