// A u-blox's own state (see receiver_state.hpp).
#include "emulator/ubx/receiver_state.hpp"

#include "emulator/model/noise/splitmix.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gpsemu::ubx {
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

/// The shared SplitMix64, stepping `state` (model/noise/splitmix.hpp).
std::uint64_t next_draw(std::uint64_t& state) {
  const std::uint64_t z = noise::splitmix64(state);
  state += 0x9E3779B97F4A7C15ULL;
  return z;
}

std::int32_t to_i32(double v) { return static_cast<std::int32_t>(std::clamp(std::round(v), -2147483648.0, 2147483647.0)); }

}  // namespace

ReceiverClock::ReceiverClock(std::uint64_t seed) : seed_(seed) { restart(); }

double ReceiverClock::gaussian() {
  // Box-Muller over two uniform draws in (0, 1].
  const double u1 = (static_cast<double>(next_draw(state_) >> 11) + 1.0) / 9007199254740992.0;
  const double u2 = static_cast<double>(next_draw(state_) >> 11) / 9007199254740992.0;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

void ReceiverClock::restart() {
  state_ = seed_ ^ 0x636c6f636bULL;  // "clock": a stream of its own
  unit_offset_ns_per_s_ = std::clamp(kUnitOffsetSigmaNsPerS * gaussian(), -kUnitOffsetMaxNsPerS, kUnitOffsetMaxNsPerS);
  drift_ns_per_s_ = unit_offset_ns_per_s_ + kDriftWanderSigmaNsPerS * gaussian();
  bias_ns_ = std::clamp(kBiasLimitNs / 2.0 * gaussian(), -kBiasLimitNs, kBiasLimitNs);
}

ClockState ReceiverClock::step(milliseconds dt, bool has_fix) {
  const double dt_s = std::max(0.0, static_cast<double>(dt.count()) / 1000.0);
  if (dt_s > 0.0) {
    const double a = std::exp(-dt_s / kDriftTauS);
    const double before = drift_ns_per_s_;
    drift_ns_per_s_ = unit_offset_ns_per_s_ + a * (drift_ns_per_s_ - unit_offset_ns_per_s_) +
                      std::sqrt(1.0 - a * a) * kDriftWanderSigmaNsPerS * gaussian();
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

ReceiverState::AtSolution ReceiverState::at(const nmea::Fix& fix) {
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

  AtSolution s;
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

void ReceiverState::restart() {
  power_on_.reset();
  last_.reset();
  ttff_.reset();
  time_valid_ = false;
  resolved_at_.reset();
  clock_.restart();
}

}  // namespace gpsemu::ubx
