// Is a receiver's log stationary? Calibration fits noise to a receiver that does not move: a
// driving log would be calibrated as noise as wide as the route. A track moves when its net
// displacement or its sustained speed is well beyond what a stationary receiver's wander gives
// (real receivers: metres of wander, a few centimetres a second). With --detrend a smooth
// trajectory (local quadratic least squares over a 10 s window) is removed first instead.
#pragma once

#include <stdexcept>
#include <string>

#include "emulator/calibration/receiver_log.hpp"

namespace gpsemu::calibration {

/// Net displacement above this is motion (metres): ~4x the widest wander of the real logs.
inline constexpr double kMaxStationaryDisplacement_m = 20.0;
/// Median speed over windows of kSpeedWindow_s above this is motion (metres per second): 10x the
/// real logs' (0.01-0.03 m/s), below a walk.
inline constexpr double kMaxStationarySpeed_mps = 0.3;
inline constexpr double kSpeedWindow_s = 30.0;
/// The detrending window (seconds): the trajectory is smooth over it, the noise's faster part is not.
inline constexpr double kDetrendWindow_s = 10.0;

struct MotionCheck {
  double displacement_m = 0.0;  ///< horizontal distance between the means of the first and last tenth
  double speed_mps = 0.0;       ///< median of |horizontal displacement| / window over windows of window_s
  double window_s = 0.0;        ///< kSpeedWindow_s, or a third of a shorter log
  bool moving = false;          ///< beyond kMaxStationaryDisplacement_m or kMaxStationarySpeed_mps
  /// "net displacement 123 m, sustained speed 2.0 m/s (median over 30 s windows)".
  [[nodiscard]] std::string describe() const;
};

/// The motion statistics of the series' horizontal axes (gaps are skipped).
[[nodiscard]] MotionCheck check_motion(const EnuSeries& series);

/// What detrend removed.
struct Detrended {
  double rms_m = 0.0;   ///< rms horizontal distance of the removed trajectory from the log's mean
  double path_m = 0.0;  ///< length of the removed trajectory (horizontal)
};

/// Removes from each axis its local quadratic least-squares fit over kDetrendWindow_s (at least 5
/// samples; windows shifted inward at the ends, gaps skipped), leaving the noise about a smooth
/// trajectory.
Detrended detrend(EnuSeries& series);

/// Thrown by calibrate for a log that moves (exit status 2 from the subcommands).
struct MotionError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

}  // namespace gpsemu::calibration
