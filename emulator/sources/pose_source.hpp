// Where the vehicle's true pose comes from: the built-in simulator, a socket fed by an external
// simulator, or a recorded trajectory. Every source answers "what was the truth at epoch t?" in
// local East/North/Up metres about the configured origin.
#pragma once

#include <optional>
#include <string>

#include "emulator/model/enu.hpp"
#include "emulator/model/time.hpp"

namespace gpsemu::sources {

/// The vehicle body's pitch and roll (degrees; a pose's optional `pitch_deg` / `roll_deg`, 0 when
/// not sent: a level vehicle). Pitch: nose up positive, -90..90; roll: right side down positive,
/// -180..180 (the aerospace yaw-pitch-roll order; docs/heading.md).
struct Tilt {
  double pitch_deg = 0.0;
  double roll_deg = 0.0;
};

/// `a` to `b` by a fraction `f` (0..1), each angle linearly.
[[nodiscard]] inline Tilt lerp_tilt(const Tilt& a, const Tilt& b, double f) {
  return {a.pitch_deg + f * (b.pitch_deg - a.pitch_deg), a.roll_deg + f * (b.roll_deg - a.roll_deg)};
}

/// The vehicle's true state at one instant, about the configured origin.
struct Truth {
  Enu position_m;    ///< East/North/Up position (metres); Up is altitude above the origin's MSL altitude
  Enu velocity_mps;  ///< East/North/Up velocity (metres per second)
  /// True heading of the vehicle body (degrees from north, clockwise, [0, 360)), when the source
  /// knows it (a pose's `yaw_deg`, the simulator's direction of travel): HDT/THS, moving-base heading.
  std::optional<double> yaw_deg;
  /// Pitch and roll of the body: where its antennas are (a moving-base baseline's down part).
  Tilt tilt;
};

class PoseSource {
 public:
  virtual ~PoseSource() = default;
  /// The truth at `t`, or nothing when the source has no current pose (stale, not started):
  /// the receiver then reports no fix.
  [[nodiscard]] virtual std::optional<Truth> truth_at(UtcNs t) = 0;
  /// Non-blocking housekeeping between epochs (read sockets). Sources without I/O do nothing.
  virtual void service() {}
  /// A file descriptor to poll for readability before calling service(), or -1.
  [[nodiscard]] virtual int poll_fd() const { return -1; }
  /// One line for the start-up banner: "sim:circle (radius 20 m, 2 m/s)".
  [[nodiscard]] virtual std::string describe() const = 0;
  /// Sources on the simulator's time base (--clock lockstep): the newest time the simulator has
  /// reached (its newest pose's `t` as UTC), nothing before the first pose. Others: nothing.
  [[nodiscard]] virtual std::optional<UtcNs> sim_time() const { return std::nullopt; }
  /// True when the source has no truth from `t` on and never will (a recorded trajectory past its
  /// end): the epoch loop stops there.
  [[nodiscard]] virtual bool ended_at(UtcNs /*t*/) const { return false; }
};

}  // namespace gpsemu::sources
