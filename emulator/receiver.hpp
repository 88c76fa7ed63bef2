// The receiver model: truth at an epoch + noise -> the Fix a receiver would report (position in
// WGS84 via GeographicLib, MSL altitude with geoid separation, speed/course, satellites, DOP).
// Pure and deterministic given the noise model's seed.
#pragma once

#include <memory>
#include <optional>

#include "emulator/geo.hpp"
#include "emulator/noise/noise_model.hpp"
#include "emulator/sources/pose_source.hpp"
#include "emulator/time.hpp"
#include "nmea/fix.hpp"

namespace gpsemu {

struct ReceiverOptions {
  double geoid_sep_m = 0.0;   ///< geoid separation written in GGA (metres); altitudes are MSL
  int satellites_used = 12;   ///< satellites in use reported while there is a fix
  double hdop = 0.8;          ///< horizontal dilution of precision reported with a fix
  nmea::FixQuality quality = nmea::FixQuality::gps;  ///< quality reported with a fix
  double course_min_speed_mps = 0.05;  ///< below this speed the last course is held
};

class Receiver {
 public:
  Receiver(const LocalFrame& frame, const ReceiverOptions& options,
           std::unique_ptr<noise::NoiseModel> noise, UtcNs first_epoch);

  /// The fix for epoch `t`; no fix when `truth` is empty. Call with non-decreasing `t`.
  [[nodiscard]] nmea::Fix fix_at(UtcNs t, const std::optional<sources::Truth>& truth);

 private:
  const LocalFrame& frame_;
  ReceiverOptions options_;
  std::unique_ptr<noise::NoiseModel> noise_;
  UtcNs first_epoch_;
  std::optional<double> last_course_deg_;
};

}  // namespace gpsemu
