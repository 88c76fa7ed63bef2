#include "emulator/model/receiver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

namespace gpsemu {
namespace {

constexpr double kVdopPerHdop = 1.5;
constexpr double kSigmaSampleRateHz = 1.0;
constexpr int kSigmaSamples = 3 * 3600;

}  // namespace

double noise_scale(nmea::FixQuality quality) {
  switch (quality) {
    case nmea::FixQuality::dgps: return 0.4;
    case nmea::FixQuality::rtk_float: return 0.1;
    case nmea::FixQuality::rtk_fixed: return 0.01;
    default: return 1.0;
  }
}

Geometry resolve_geometry(const ReceiverOptions& options) {
  Geometry g;
  const double sigma_h_m = std::hypot(options.noise_sigma_m.east_m, options.noise_sigma_m.north_m);
  g.hdop = options.hdop ? *options.hdop : std::clamp(sigma_h_m / kUereM, kMinDerivedHdop, kMaxDerivedHdop);
  if (options.satellites_used) {
    g.satellites_used = std::clamp(*options.satellites_used, 1, static_cast<int>(nmea::max_satellites));
  } else {
    const double n = std::round(std::pow(kHdopSqrtSatellites / g.hdop, 2.0));
    g.satellites_used = static_cast<int>(std::clamp(n, double{kMinDerivedSatellites}, double{kMaxDerivedSatellites}));
  }
  g.satellites_in_view =
      std::min(static_cast<int>(nmea::max_satellites), g.satellites_used + 2 + g.satellites_used / 4);
  g.vdop = kVdopPerHdop * g.hdop;
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
      geometry_(resolve_geometry(options)),
      sky_(options.sky_seed, geometry_.satellites_in_view),
      noise_sigma_h_m_(std::hypot(options.noise_sigma_m.east_m, options.noise_sigma_m.north_m)) {}

nmea::Fix Receiver::fix_at(UtcNs t, const std::optional<sources::Truth>& truth) {
  nmea::Fix fix;
  fix.time_utc = std::chrono::floor<std::chrono::milliseconds>(t);
  // The noise process runs whether or not there is a fix, so a fix that returns after an outage
  // continues the same smooth wander instead of restarting it.
  const auto since = t - first_epoch_;
  const Enu raw_error = noise_->offset_at(since);
  const double since_s = std::chrono::duration<double>(since).count();
  const ReceiverPhase phase = phase_at(options_, since_s);
  if (phase == ReceiverPhase::outage) return fix;  // nothing in view

  const int in_view = sky_.in_view();
  int acquired = in_view;
  if (phase == ReceiverPhase::acquiring) {
    acquired = static_cast<int>(std::floor(in_view * since_s / options_.cold_start_s));
  }
  const bool fixing = truth && (phase == ReceiverPhase::two_d || phase == ReceiverPhase::three_d);
  const bool two_d = phase == ReceiverPhase::two_d;
  const int used = !fixing ? 0 : two_d ? std::min(kTwoDSatellites, in_view) : geometry_.satellites_used;
  int satellites_used = 0;
  if (options_.satellite_details) {
    sky_.fill(since_s, acquired, used, fix);
    for (int i = 0; i < fix.satellites_in_view; ++i) satellites_used += fix.satellites[static_cast<std::size_t>(i)].used;
  } else {
    // The counts Sky::fill gives: the first `acquired` of the acquisition order are listed, and
    // the `used` highest of them (distinct ranks) are used.
    fix.satellites_in_view = std::clamp(acquired, 0, in_view);
    for (int i = 0; i < fix.satellites_in_view; ++i) fix.satellites[static_cast<std::size_t>(i)].used = i < used;
    satellites_used = std::clamp(used, 0, fix.satellites_in_view);
  }
  if (!fixing) return fix;

  // A 2-D fix from 3 satellites has a poorer geometry: HDOP as for 3 satellites, and the
  // horizontal noise grows by the same factor.
  const double hdop = two_d ? std::max(geometry_.hdop, kHdopSqrtSatellites / std::sqrt(double{kTwoDSatellites}))
                            : geometry_.hdop;
  const double scale = noise_scale(options_.quality);
  const double h_scale = scale * hdop / geometry_.hdop;
  const Enu error{h_scale * raw_error.east_m, h_scale * raw_error.north_m, scale * raw_error.up_m};

  const Geodetic position = frame_.to_geodetic(truth->position_m + error);
  fix.quality = options_.quality;
  fix.dimension = two_d ? nmea::FixDimension::two_d : nmea::FixDimension::three_d;
  fix.lat_deg = position.lat_deg;
  fix.lon_deg = position.lon_deg;
  fix.alt_msl_m = position.alt_m;
  fix.geoid_sep_m = options_.geoid_sep_m;
  const double ve = truth->velocity_mps.east_m;
  const double vn = truth->velocity_mps.north_m;
  fix.speed_mps = std::hypot(ve, vn);
  if (fix.speed_mps >= options_.course_min_speed_mps) {
    double course = std::atan2(ve, vn) * 180.0 / std::numbers::pi;
    if (course < 0.0) course += 360.0;
    last_course_deg_ = course;
  }
  fix.course_deg_true = last_course_deg_;
  fix.satellites_used = satellites_used;
  fix.hdop = hdop;
  fix.vdop = kVdopPerHdop * hdop;
  // In 3-D, hdop is geometry_.hdop and the same arithmetic gave geometry_.pdop.
  fix.pdop = two_d ? std::hypot(fix.hdop, fix.vdop) : geometry_.pdop;
  const Enu& sigma = options_.noise_sigma_m;
  fix.sigma_lat_m = h_scale * sigma.north_m;
  fix.sigma_lon_m = h_scale * sigma.east_m;
  fix.sigma_alt_m = scale * sigma.up_m;
  fix.range_rms_m = h_scale * noise_sigma_h_m_ / hdop;
  return fix;
}

}  // namespace gpsemu
