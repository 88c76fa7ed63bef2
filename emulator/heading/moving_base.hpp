// A moving-base pair on one vehicle (ArduPilot GPS_TYPE 17/18, PX4 GPS yaw): two receivers of a
// fleet, the moving base and the rover, each with its antenna at an offset in the body frame.
// The base writes RTCM3 (rtcm3_base.hpp) that the autopilot forwards to the rover; the rover
// reports where it is relative to the base (NAV-RELPOSNED) and so the vehicle's heading. Pure:
// the truth, the time of the last corrections and a seed in, the relative position out.
//
// Geometry: an antenna at (forward, right, down) metres of the body frame sits, for a vehicle of
// yaw psi (degrees true), pitch theta and roll phi (degrees; a pose's pitch_deg / roll_deg, 0 when
// not sent), at R(psi) R(theta) R(phi) (forward, right, down) in north/east/down from the vehicle's
// reference point (the pose): the aerospace yaw-pitch-roll rotation. Level (theta = phi = 0):
//   north = forward cos psi - right sin psi,  east = forward sin psi + right cos psi,  down = down.
// The baseline is rover antenna - base antenna: its length and down part follow the attitude, the
// heading is that of its horizontal part.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "emulator/model/enu.hpp"
#include "emulator/model/noise/rng.hpp"
#include "emulator/model/time.hpp"
#include "emulator/sources/pose_source.hpp"
#include "emulator/model/epoch.hpp"

namespace gpsemu::heading {

/// What a receiver is in a moving-base pair (`role`).
enum class Role { standalone, moving_base, rover };

/// "standalone", "moving-base", "rover".
[[nodiscard]] const char* to_string(Role role);
/// The role named `text`; throws std::invalid_argument naming the accepted values.
[[nodiscard]] Role parse_role(const std::string& text);

/// An antenna's place in the vehicle's body frame (metres): forward, right, down of the pose's point.
struct AntennaOffset {
  double forward_m = 0.0;
  double right_m = 0.0;
  double down_m = 0.0;
};

/// "FWD,RIGHT,DOWN" in metres, each within +-100; throws std::invalid_argument naming the key.
[[nodiscard]] AntennaOffset parse_antenna_offset(const std::string& text);

/// A receiver's part in a pair (settings.hpp: ReceiverSettings::moving_base).
struct MovingBaseOptions {
  Role role = Role::standalone;
  AntennaOffset antenna;        ///< this receiver's antenna (`antenna-offset`)
  AntennaOffset base_antenna;   ///< rover: its base's antenna (from the fleet's moving base)
  /// Rover: 1-sigma error of each relPos component (metres): an RTK-fixed baseline, ~1 cm.
  double baseline_sigma_m = 0.01;
  /// Rover: relPosValid only while the base's RTCM3 arrived within this long (seconds).
  double corrections_timeout_s = 1.5;
};

/// The offset (metres, east/north/up) of `antenna` from the vehicle's point at yaw `yaw_deg`,
/// pitch `pitch_deg` and roll `roll_deg`.
[[nodiscard]] Enu offset_enu(const AntennaOffset& antenna, double yaw_deg, double pitch_deg = 0.0,
                             double roll_deg = 0.0);

/// Base antenna -> rover antenna in metres North/East/Down at yaw `yaw_deg`.
struct Ned {
  double north_m = 0.0, east_m = 0.0, down_m = 0.0;
};
[[nodiscard]] Ned baseline_ned(const AntennaOffset& base, const AntennaOffset& rover, double yaw_deg,
                               double pitch_deg = 0.0, double roll_deg = 0.0);

/// The rover's NAV-RELPOSNED values, epoch by epoch, with its own noise (a seeded stream).
class RoverRelPos {
 public:
  RoverRelPos(const MovingBaseOptions& options, std::uint64_t seed);

  /// At epoch `t`: valid (carrSoln fixed, diffSoln, heading valid when the baseline has a
  /// horizontal length) when the truth has a yaw and corrections arrived within the timeout;
  /// otherwise only isMoving. `last_corrections`: when the base's RTCM3 last arrived.
  [[nodiscard]] RelativePosition at(UtcNs t, const std::optional<sources::Truth>& truth,
                                  const std::optional<UtcNs>& last_corrections);

 private:
  MovingBaseOptions options_;
  noise::Rng rng_;
};

}  // namespace gpsemu::heading
