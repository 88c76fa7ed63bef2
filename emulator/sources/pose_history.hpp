// The recent poses of an external simulator and the truth they imply at an epoch time: a bounded
// ring buffer (allocated once), linear interpolation between the poses around the epoch,
// extrapolation with the last velocity over a short horizon, and no truth once the newest pose at
// the epoch is older than the timeout; a pose that jumps farther than a vehicle can go (within
// the timeout) is refused. Pure: every time is passed in, nothing reads a clock.
//
// Time base: each pose holds at its arrival time (CLOCK_REALTIME, i.e. UTC; the kernel's receive
// time stamp for UDP). The sender's own time `t`, when given, is only used to refuse reordered
// datagrams and to compute speed from the track; see docs/pose-input.md for the trade-off.
// Lockstep time base (--clock lockstep): the caller places each pose at base + `t` instead, so
// the history is keyed by sender time; nothing here changes (every time is the caller's).
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <vector>

#include "emulator/model/enu.hpp"
#include "emulator/sources/pose_message.hpp"
#include "emulator/sources/pose_source.hpp"
#include "emulator/model/time.hpp"

namespace gpsemu::sources {

/// One pose placed in time, in local ENU metres about the origin.
struct TimedPose {
  UtcNs time{};                         ///< when the pose holds: its arrival time, or base + t in lockstep (UTC)
  std::optional<double> sender_time_s;  ///< the sender's `t` (seconds), when given
  Enu position_m;                       ///< East/North/Up position (metres)
  std::optional<Enu> velocity_mps;      ///< East/North/Up velocity (metres per second), when given
  std::optional<double> yaw_deg;        ///< true heading (degrees, [0, 360)), when given
  Tilt tilt;                            ///< pitch and roll (degrees), 0 when not given
};

struct PoseHistoryOptions {
  std::size_t capacity = 2048;                          ///< poses kept (>= 2); with min_spacing, >= 1 s of history
  std::chrono::nanoseconds timeout{std::chrono::seconds(1)};         ///< older than this: no truth (--pose-timeout)
  std::chrono::nanoseconds horizon{std::chrono::milliseconds(200)};  ///< longest extrapolation (--pose-horizon)
  std::chrono::nanoseconds min_spacing{std::chrono::microseconds(500)};  ///< closer poses are a flood
  /// Shortest time base for speed from the track (seconds): closer poses are skipped back over,
  /// so arrival-time jitter does not turn into speed noise.
  double min_track_baseline_s = 0.01;
};

/// What push() did with a pose.
enum class PushResult {
  accepted,
  restarted,     ///< accepted after clearing the history: the sender's time or the clock jumped back
  out_of_order,  ///< refused: sender time not after the newest pose's (within the timeout)
  flood,         ///< refused: less than min_spacing after the newest pose
  too_fast,      ///< refused: farther from the newest pose (within the timeout) than a vehicle can go
};

/// The reason a source counts for a pose push() refused; nothing when it was taken (accepted, restarted).
[[nodiscard]] std::optional<PoseReject> refusal_of(PushResult result);

class PoseHistory {
 public:
  /// Throws std::invalid_argument for a capacity below 2 or a non-positive timeout.
  explicit PoseHistory(const PoseHistoryOptions& options = {});

  /// Adds a pose. Poses normally come in arrival order; see PushResult for the others.
  PushResult push(const TimedPose& pose);

  /// The truth at `t`: interpolated between the poses around `t`; after the newest pose,
  /// extrapolated with its velocity for at most the horizon and then held (speed 0); nothing
  /// before the first pose or when the newest pose at or before `t` is older than the timeout.
  /// Velocity: the senders' velocities (interpolated) when both poses carry one, otherwise the
  /// track's (from sender times when both poses have `t`, else arrival times). Yaw: interpolated
  /// along the shorter way round when both poses carry one, else the earlier pose's; held after
  /// the newest pose.
  [[nodiscard]] std::optional<Truth> sample(UtcNs t) const;

  /// True when sample(t) would return a truth.
  [[nodiscard]] bool fresh_at(UtcNs t) const;

  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] bool empty() const { return size_ == 0; }
  [[nodiscard]] const TimedPose& newest() const { return at(size_ - 1); }
  /// The oldest pose held; only when !empty().
  [[nodiscard]] const TimedPose& oldest() const { return at(0); }
  void clear() { size_ = 0; }
  [[nodiscard]] const PoseHistoryOptions& options() const { return options_; }

 private:
  /// The i-th pose, oldest first.
  [[nodiscard]] const TimedPose& at(std::size_t i) const { return ring_[(head_ + i) % ring_.size()]; }
  /// Index of the newest pose at or before `t`, or nothing.
  [[nodiscard]] std::optional<std::size_t> index_at_or_before(UtcNs t) const;
  /// Speed from the track ending at pose `to`, or zero when there is no usable earlier pose.
  [[nodiscard]] Enu track_velocity(std::size_t to) const;
  [[nodiscard]] bool is_gap(const TimedPose& a, const TimedPose& b) const;
  /// True when `b` is farther from `a` than kMaxJumpSlackM + kMaxSpeedMps * dt (dt from the
  /// sender times when both carry one, else from their times).
  [[nodiscard]] static bool is_jump(const TimedPose& a, const TimedPose& b);

  PoseHistoryOptions options_;
  std::vector<TimedPose> ring_;  ///< fixed size: no allocation after construction
  std::size_t head_ = 0;         ///< index of the oldest pose in ring_
  std::size_t size_ = 0;
};

}  // namespace gpsemu::sources
