// Velocity error (see velocity_noise.hpp).
#include "emulator/model/noise/velocity_noise.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace gpsemu::noise {
namespace {

constexpr std::uint64_t kVelocityStream = 0x76656c6f63697479ULL;  // "velocity"

void check(double v, double lo, double hi, const char* name) {
  if (!(v >= lo && v <= hi)) {
    throw std::invalid_argument(std::string(name) + ": " + std::to_string(v) + " is outside [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
}

}  // namespace

double VelocityNoiseParams::horizontal_sigma_mps() const {
  return std::sqrt(white_sigma_mps * white_sigma_mps + wander_sigma_mps * wander_sigma_mps);
}

void validate(const VelocityNoiseParams& p) {
  check(p.white_sigma_mps, 0.0, 10.0, "velocity-noise");
  check(p.wander_sigma_mps, 0.0, 10.0, "velocity-wander");
  check(p.wander_tau_s, 0.1, 86400.0, "velocity-wander-tau");
  check(p.vertical_ratio, 0.1, 10.0, "velocity-vertical-ratio");
  check(p.static_clamp_mps, 0.0, 1.0, "velocity-static-clamp");
}

VelocityNoise::VelocityNoise(const VelocityNoiseParams& params, std::uint64_t seed)
    : params_(params), rng_(seed, kVelocityStream) {
  validate(params_);  // a library caller's options are checked as the flags are
  reset();
}

void VelocityNoise::reset() {
  rng_.reset();
  last_.reset();
  // The correlated part starts from its stationary distribution, as a receiver switched on earlier.
  const double s = params_.wander_sigma_mps;
  wander_ = {s * rng_.ziggurat_normal(), s * rng_.ziggurat_normal(), params_.vertical_ratio * s * rng_.ziggurat_normal()};
}

Enu VelocityNoise::error_at(std::chrono::nanoseconds since_start) {
  const double s = params_.wander_sigma_mps;
  if (last_ && s > 0.0) {
    const std::chrono::nanoseconds dt = since_start - *last_;
    if (dt > std::chrono::nanoseconds::zero()) {
      if (dt != step_dt_) {
        const double dt_s = std::chrono::duration<double>(dt).count();
        step_a_ = std::exp(-dt_s / params_.wander_tau_s);
        step_b_ = std::sqrt(1.0 - step_a_ * step_a_) * s;
        step_dt_ = dt;
      }
      const double a = step_a_, b = step_b_;
      wander_.east_m = a * wander_.east_m + b * rng_.ziggurat_normal();
      wander_.north_m = a * wander_.north_m + b * rng_.ziggurat_normal();
      wander_.up_m = a * wander_.up_m + params_.vertical_ratio * b * rng_.ziggurat_normal();
    }
  }
  last_ = since_start;
  const double w = params_.white_sigma_mps;
  if (w == 0.0) return wander_;
  return {wander_.east_m + w * rng_.ziggurat_normal(), wander_.north_m + w * rng_.ziggurat_normal(),
          wander_.up_m + params_.vertical_ratio * w * rng_.ziggurat_normal()};
}

}  // namespace gpsemu::noise
