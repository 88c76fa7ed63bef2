// A receiver's own status and clock (see receiver_clock.hpp).
#include "emulator/model/receiver_clock.hpp"

#include <algorithm>
#include <cmath>

namespace gpsemu {
namespace {

using std::chrono::milliseconds;

constexpr double kUnitOffsetSigmaNsPerS = 200.0;  // TCXO frequency offset between units (0.2 ppm)
constexpr double kUnitOffsetMaxNsPerS = 500.0;    // +-0.5 ppm
constexpr double kDriftWanderSigmaNsPerS = 5.0;   // stationary wander of the drift around the offset
constexpr double kDriftTauS = 300.0;              // correlation time of the wander (temperature)
constexpr double kBiasLimitNs = 500'000.0;        // the bias is stepped by 1 ms beyond +-0.5 ms
constexpr double kBiasStepNs = 1'000'000.0;
constexpr std::uint32_t kFixTimeAccuracyNs = 20;
constexpr std::uint32_t kFixFrequencyAccuracyPsPerS = 500;
constexpr std::uint32_t kNoFixTimeAccuracyNs = 1'000'000'000;
constexpr std::uint32_t kNoFixFrequencyAccuracyPsPerS = 1'000'000;

constexpr std::uint64_t kClockStream = 0x636c6f636bULL;  // "clock"

/// Rounded half away from zero, clamped to the int32 range (without libm's round: an epoch's cost).
std::int32_t to_i32(double v) {
  const double c = std::clamp(v, -2147483648.0, 2147483647.0);
  return static_cast<std::int32_t>(c >= 0.0 ? std::min(c + 0.5, 2147483647.0) : c - 0.5);
}

}  // namespace

ReceiverClock::ReceiverClock(std::uint64_t seed) : rng_(seed, kClockStream) { restart(); }

void ReceiverClock::restart() {
  rng_.reset();
  step_dt_ = milliseconds{-1};
  unit_offset_ns_per_s_ = std::clamp(kUnitOffsetSigmaNsPerS * rng_.ziggurat_normal(), -kUnitOffsetMaxNsPerS, kUnitOffsetMaxNsPerS);
  drift_ns_per_s_ = unit_offset_ns_per_s_ + kDriftWanderSigmaNsPerS * rng_.ziggurat_normal();
  bias_ns_ = std::clamp(kBiasLimitNs / 2.0 * rng_.ziggurat_normal(), -kBiasLimitNs, kBiasLimitNs);
}

ClockState ReceiverClock::step(milliseconds dt, bool has_fix) {
  const double dt_s = std::max(0.0, static_cast<double>(dt.count()) / 1000.0);
  if (dt_s > 0.0) {
    if (dt != step_dt_) {  // the same interval epoch after epoch: its coefficients once
      step_a_ = std::exp(-dt_s / kDriftTauS);
      step_b_ = std::sqrt(1.0 - step_a_ * step_a_) * kDriftWanderSigmaNsPerS;
      step_dt_ = dt;
    }
    const double before = drift_ns_per_s_;
    drift_ns_per_s_ = unit_offset_ns_per_s_ + step_a_ * (drift_ns_per_s_ - unit_offset_ns_per_s_) +
                      step_b_ * rng_.ziggurat_normal();
    bias_ns_ += 0.5 * (before + drift_ns_per_s_) * dt_s;
    while (bias_ns_ > kBiasLimitNs) bias_ns_ -= kBiasStepNs;
    while (bias_ns_ < -kBiasLimitNs) bias_ns_ += kBiasStepNs;
  }
  ClockState c;
  c.bias_ns = to_i32(bias_ns_);
  c.drift_ns_per_s = to_i32(drift_ns_per_s_);
  c.time_accuracy_ns = has_fix ? kFixTimeAccuracyNs : kNoFixTimeAccuracyNs;
  c.frequency_accuracy_ps_per_s = has_fix ? kFixFrequencyAccuracyPsPerS : kNoFixFrequencyAccuracyPsPerS;
  return c;
}

ReceiverStatus ReceiverStatusTracker::at(const nmea::Fix& fix) {
  const nmea::UtcTime t = fix.time_utc;
  if (!power_on_) {
    // A fix at the first solution: the receiver was on (hot) before it; its time is known.
    const bool hot = fix.has_fix();
    power_on_ = hot ? t - kHotStartTtff : t;
    if (hot) {
      ttff_ = kHotStartTtff;
      time_valid_ = true;
      resolved_at_ = t - kConfirmDelay;
    }
  }
  const milliseconds dt = last_ ? std::max(milliseconds{0}, t - *last_) : milliseconds{0};
  last_ = t;

  ReceiverStatus s;
  s.since_start = t - *power_on_;
  if (!ttff_ && fix.has_fix()) ttff_ = s.since_start;
  s.time_to_first_fix = ttff_.value_or(milliseconds{0});

  if (!fix.has_fix() && fix.satellites_in_view == 0) {  // nothing tracked: no time
    time_valid_ = false;
    resolved_at_.reset();
  } else {
    time_valid_ = true;
    if (!resolved_at_ && fix.has_fix()) resolved_at_ = t;
  }
  s.time.valid = time_valid_;
  s.time.resolved = resolved_at_.has_value();
  s.time.confirmed = s.time.resolved && t - *resolved_at_ >= kConfirmDelay;
  s.clock = clock_.step(dt, fix.has_fix());
  return s;
}

void ReceiverStatusTracker::restart() {
  power_on_.reset();
  last_.reset();
  ttff_.reset();
  time_valid_ = false;
  resolved_at_.reset();
  clock_.restart();
}

}  // namespace gpsemu
