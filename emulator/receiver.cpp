#include "emulator/receiver.hpp"

#include <cmath>
#include <numbers>

namespace gpsemu {

Receiver::Receiver(const LocalFrame& frame, const ReceiverOptions& options,
                   std::unique_ptr<noise::NoiseModel> noise, UtcNs first_epoch)
    : frame_(frame), options_(options), noise_(std::move(noise)), first_epoch_(first_epoch) {}

nmea::Fix Receiver::fix_at(UtcNs t, const std::optional<sources::Truth>& truth) {
  nmea::Fix fix;
  fix.time_utc = std::chrono::floor<std::chrono::milliseconds>(t);
  // The noise process runs whether or not there is a fix, so a fix that returns after an outage
  // continues the same smooth wander instead of restarting it.
  const Enu error = noise_->offset_at(t - first_epoch_);
  if (!truth) return fix;

  const Geodetic position = frame_.to_geodetic(truth->position_m + error);
  fix.quality = options_.quality;
  fix.dimension = nmea::FixDimension::three_d;
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
  fix.satellites_used = options_.satellites_used;
  fix.hdop = options_.hdop;
  fix.vdop = 1.5 * options_.hdop;
  fix.pdop = std::hypot(fix.hdop, fix.vdop);
  return fix;
}

}  // namespace gpsemu
