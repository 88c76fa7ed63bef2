#include "emulator/sources/pose_history.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gpsemu::sources {
namespace {

double seconds(std::chrono::nanoseconds d) { return std::chrono::duration<double>(d).count(); }

Enu lerp(const Enu& a, const Enu& b, double f) { return a + f * (b - a); }

}  // namespace

PoseHistory::PoseHistory(const PoseHistoryOptions& options) : options_(options) {
  if (options_.capacity < 2) throw std::invalid_argument("pose history capacity must be at least 2");
  if (options_.timeout <= std::chrono::nanoseconds::zero()) {
    throw std::invalid_argument("pose timeout must be > 0 seconds");
  }
  if (options_.horizon < std::chrono::nanoseconds::zero()) {
    throw std::invalid_argument("pose extrapolation horizon must be >= 0 seconds");
  }
  ring_.resize(options_.capacity);
}

PushResult PoseHistory::push(const TimedPose& pose) {
  PushResult result = PushResult::accepted;
  if (size_ > 0) {
    const TimedPose& last = newest();
    const double timeout_s = seconds(options_.timeout);
    if (pose.sender_time_s && last.sender_time_s && *pose.sender_time_s <= *last.sender_time_s) {
      // A small step back is a reordered or repeated datagram; a large one a restarted simulator.
      if (*last.sender_time_s - *pose.sender_time_s <= timeout_s) return PushResult::out_of_order;
      result = PushResult::restarted;
    } else if (pose.time < last.time - options_.timeout) {
      result = PushResult::restarted;  // the system clock was stepped back
    } else if (pose.time < last.time + options_.min_spacing) {
      return PushResult::flood;
    }
    // Poses across a gap are never interpolated, so only a jump within the timeout matters.
    if (result == PushResult::accepted && !is_gap(last, pose) && is_jump(last, pose)) return PushResult::too_fast;
  }
  if (result == PushResult::restarted) clear();
  if (size_ == ring_.size()) {  // full: overwrite the oldest
    head_ = (head_ + 1) % ring_.size();
    --size_;
  }
  ring_[(head_ + size_) % ring_.size()] = pose;
  ++size_;
  return result;
}

std::optional<std::size_t> PoseHistory::index_at_or_before(UtcNs t) const {
  if (size_ == 0 || t < at(0).time) return std::nullopt;
  std::size_t lo = 0, hi = size_;  // at(lo).time <= t; answer in [lo, hi)
  while (hi - lo > 1) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (at(mid).time <= t) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

bool PoseHistory::is_gap(const TimedPose& a, const TimedPose& b) const {
  return b.time - a.time > options_.timeout;
}

bool PoseHistory::is_jump(const TimedPose& a, const TimedPose& b) {
  const double dt_s = (a.sender_time_s && b.sender_time_s) ? *b.sender_time_s - *a.sender_time_s
                                                           : seconds(b.time - a.time);
  const Enu d = b.position_m - a.position_m;
  const double distance_m = std::sqrt(d.east_m * d.east_m + d.north_m * d.north_m + d.up_m * d.up_m);
  return distance_m > kMaxJumpSlackM + kMaxSpeedMps * std::max(dt_s, 0.0);
}

Enu PoseHistory::track_velocity(std::size_t to) const {
  const TimedPose& b = at(to);
  for (std::size_t from = to; from-- > 0;) {
    const TimedPose& a = at(from);
    if (is_gap(a, at(from + 1))) break;
    const double dt = (a.sender_time_s && b.sender_time_s) ? *b.sender_time_s - *a.sender_time_s
                                                           : seconds(b.time - a.time);
    if (dt >= options_.min_track_baseline_s) return (1.0 / dt) * (b.position_m - a.position_m);
  }
  return {};
}

std::optional<Truth> PoseHistory::sample(UtcNs t) const {
  const auto n = index_at_or_before(t);
  if (!n) return std::nullopt;
  const TimedPose& a = at(*n);
  const auto age = t - a.time;
  if (age > options_.timeout) return std::nullopt;

  if (*n + 1 < size_ && !is_gap(a, at(*n + 1))) {
    const TimedPose& b = at(*n + 1);
    const double f = seconds(age) / seconds(b.time - a.time);
    const Enu velocity = (a.velocity_mps && b.velocity_mps) ? lerp(*a.velocity_mps, *b.velocity_mps, f)
                                                             : track_velocity(*n + 1);
    return Truth{lerp(a.position_m, b.position_m, f), velocity, interpolate_yaw_deg(a.yaw_deg, b.yaw_deg, f),
                 lerp_tilt(a.tilt, b.tilt, f)};
  }
  // After the newest pose (or the last one before a gap): extrapolate, then hold.
  const Enu velocity = a.velocity_mps ? *a.velocity_mps : track_velocity(*n);
  if (age > options_.horizon) return Truth{a.position_m + seconds(options_.horizon) * velocity, Enu{}, a.yaw_deg, a.tilt};
  return Truth{a.position_m + seconds(age) * velocity, velocity, a.yaw_deg, a.tilt};
}

bool PoseHistory::fresh_at(UtcNs t) const {
  const auto n = index_at_or_before(t);
  return n && t - at(*n).time <= options_.timeout;
}

std::optional<PoseReject> refusal_of(PushResult result) {
  switch (result) {
    case PushResult::out_of_order: return PoseReject::out_of_order;
    case PushResult::flood: return PoseReject::flood;
    case PushResult::too_fast: return PoseReject::too_fast;
    case PushResult::accepted:
    case PushResult::restarted: return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace gpsemu::sources
