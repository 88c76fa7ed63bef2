// Is a receiver's log stationary? Calibration fits noise to a receiver that does not move: a
// driving log would be calibrated as noise as wide as the route. When the log states speeds over
// ground (RMC, VTG: the receiver's Doppler velocity, which its slow position wander does not
// show, while the velocity's own noise does not add up to a track), the receiver is read: it moves
// when its reported speed, sustained over windows, is at least kReportedSpeedLimit_mps, its
// track goes at least kTrackShareOfReported as fast and kMinTrackSpeed_mps, and its smoothed track
// (the means of its tenths) spans more than kTrackExtentInScatter times the scatter of its
// positions about those means (an older chipset reports 5-10 cm/s at rest while its position only
// scatters about one place). Otherwise a track moves
// when its net displacement or its sustained speed is well beyond what the log's own noise
// explains (limits scaled by the noise, see check_motion and docs/noise-and-calibration.md). With --detrend a
// smooth trajectory (local quadratic least squares over a 10 s window) is removed first instead.
#pragma once

#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include "emulator/calibration/receiver_log.hpp"

namespace gpsemu::calibration {

/// The limits never go below these floors (a receiver quiet to centimetres still wanders metres
/// over hours, and speeds under 5 cm/s over half a minute are within every real log's).
inline constexpr double kMinDisplacementLimit_m = 2.0;
inline constexpr double kMinSpeedLimit_mps = 0.05;
/// The displacement limit in horizontal standard deviations about a straight line: wander slower
/// than the log is locally straight (the real logs of 2-3 minutes reach 13 of them).
inline constexpr double kDisplacementInSd = 25.0;
/// The speed limit in what a random walk with the noise's first-difference spread travels over a
/// window (the real logs reach 2.7 of them).
inline constexpr double kSpeedInWalks = 6.0;
inline constexpr double kSpeedWindow_s = 30.0;
/// A sustained reported speed over ground at least this is motion when the track's own sustained
/// speed is at least kTrackShareOfReported of it and kMinTrackSpeed_mps. Stationary receivers
/// report 0-6 cm/s (tests/data/real: Quectel 0, Telit 0.5 cm/s, ZED-F9P 6 cm/s of undirected
/// velocity noise) while their track goes 0-3 cm/s; on a drifting boat or a creeping vehicle the
/// track goes as fast as the reported speed. (A receiver that reports 0 below a threshold, u-blox's
/// static hold, hides motion slower than it.)
inline constexpr double kReportedSpeedLimit_mps = 0.05;
inline constexpr double kTrackShareOfReported = 0.6;
inline constexpr double kMinTrackSpeed_mps = 0.04;
/// ...and at most this multiple of it: a receiver's Doppler velocity is good to centimetres a
/// second, so a track much faster than the receiver says it moves is its position error moving
/// (a receiver settling after its first fix: gpsd's ublox-8.log, a MAX-M8Q on a desk, goes 12.7 m
/// north in 72 s, 0.14 m/s, while it reports 0.05 m/s; rx210.log's M8 jumps about at 0.37 m/s
/// over 13 s while it reports 0.07 m/s). On a drifting boat or a creeping vehicle the two agree.
inline constexpr double kTrackMultipleOfReported = 2.0;
/// ...and when the smoothed track (the mean positions of the log's kTrackBlocks consecutive
/// blocks) spans more than this many times the scatter of the positions about their block's mean,
/// and kMinDisplacementLimit_m. A steady drift of L spans 0.9 L against a scatter of at least
/// L / 10 / sqrt(12) (31 of them); a stationary receiver's block means stay within its scatter
/// (1-2 of them for noise correlated over minutes; the generated logs of motion_test.cpp).
inline constexpr double kTrackExtentInScatter = 4.0;
inline constexpr int kTrackBlocks = 10;
/// The detrending window (seconds): the trajectory is smooth over it, the noise's faster part is not.
inline constexpr double kDetrendWindow_s = 10.0;

struct MotionCheck {
  double displacement_m = 0.0;  ///< horizontal distance between the means of the first and last tenth
  double speed_mps = 0.0;       ///< median of |horizontal displacement| / window over windows of window_s
  double window_s = 0.0;        ///< kSpeedWindow_s, or a third of a shorter log
  /// The log's noise: horizontal standard deviation about each axis's least-squares line in time
  /// (a steady drift removed), and the horizontal first-difference standard deviation (metres per
  /// sample) of the series with its smooth trajectory removed (detrend: motion removed).
  double noise_sd_m = 0.0, noise_d1_sd_m = 0.0;
  /// max(kMinDisplacementLimit_m, kDisplacementInSd x noise_sd_m).
  double displacement_limit_m = 0.0;
  /// max(kMinSpeedLimit_mps, kSpeedInWalks x noise_d1_sd_m x sqrt(samples in window_s) / window_s).
  double speed_limit_mps = 0.0;
  /// The receiver's own speed over ground: median over windows of window_s of the mean reported
  /// speed in each; empty when the log states none (the noise's limits decide then).
  std::optional<double> reported_speed_mps;
  std::size_t speed_reports = 0;
  /// The smoothed track: the largest distance between the mean positions of the log's
  /// kTrackBlocks blocks, and the rms horizontal distance of the positions from their block's mean.
  double track_extent_m = 0.0, block_scatter_m = 0.0;
  /// max(kMinDisplacementLimit_m, kTrackExtentInScatter x block_scatter_m).
  double track_extent_limit_m = 0.0;
  bool moving = false;          ///< beyond the limits (the reported speed's when there is one)
  /// "net displacement 123 m, sustained speed 2.0 m/s (median over 30 s windows)".
  [[nodiscard]] std::string describe() const;
  /// "limits for this log's noise (0.12 m about a line, 0.034 m first differences): 3.0 m and 0.05 m/s".
  [[nodiscard]] std::string describe_limits() const;
};

/// The motion statistics of the series' horizontal axes (gaps are skipped), and of the speeds over
/// ground the receiver reported (ReceiverLog::speeds; none: the noise's limits decide).
[[nodiscard]] MotionCheck check_motion(const EnuSeries& series, std::span<const SpeedReport> speeds = {});

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
