#include "emulator/model/noise/chrono_model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace gpsemu::noise {

void validate_chrono_params(const ChronoParams& p) {
  std::ostringstream os;
  const auto bad_nonnegative = [](double x) { return !(x >= 0.0) || !std::isfinite(x); };
  if (!std::isfinite(p.mean)) {
    os << "chrono.mean must be finite (got " << p.mean << ")";
  } else if (bad_nonnegative(p.sigma)) {
    os << "chrono.sigma must be finite and >= 0 (got " << p.sigma << ")";
  } else if (!(p.update_rate_hz > 0.0) || !(p.update_rate_hz <= kChronoMaxRateHz)) {
    os << "chrono.update_rate_hz must be > 0 and <= " << kChronoMaxRateHz << " Hz (got "
       << p.update_rate_hz << ")";
  } else if (bad_nonnegative(p.v_max_mps)) {
    os << "chrono.v_max_mps must be finite and >= 0 (got " << p.v_max_mps << ")";
  } else if (bad_nonnegative(p.a_max_mps2)) {
    os << "chrono.a_max_mps2 must be finite and >= 0 (got " << p.a_max_mps2 << ")";
  }
  if (!os.str().empty()) throw std::invalid_argument(os.str());
}

void chrono_step(const ChronoParams& k, const std::array<double, 3>& z, ChronoState& s) {
  const double dt = 1.0 / k.update_rate_hz;
  for (std::size_t i = 0; i < 3; ++i) {
    const double mean = -kChronoGain * k.sigma * s.p_m[i] / kChronoPMax;
    const double a = std::clamp(mean + k.sigma * z[i], -k.a_max_mps2, k.a_max_mps2);
    s.v_mps[i] += a * dt;
  }
  const double speed =
      std::sqrt(s.v_mps[0] * s.v_mps[0] + s.v_mps[1] * s.v_mps[1] + s.v_mps[2] * s.v_mps[2]);
  if (speed > k.v_max_mps) {
    for (double& v : s.v_mps) v = v / speed * k.v_max_mps;
  }
  for (std::size_t i = 0; i < 3; ++i) s.p_m[i] += s.v_mps[i] * dt;
}

ChronoNoise::ChronoNoise(const ChronoParams& params, std::uint64_t seed)
    : params_(params), rng_(seed, 0) {
  validate_chrono_params(params_);
  restart();
}

void ChronoNoise::step() {
  const std::array<double, 3> z{rng_.normal(), rng_.normal(), rng_.normal()};
  chrono_step(params_, z, state_);
}

void ChronoNoise::restart() {
  rng_.reset();
  state_ = {};
  prev_m_ = state_.p_m;
  step();
  base_ = 0;
}

Enu ChronoNoise::offset_at(std::chrono::nanoseconds since_start) {
  const double x =
      std::max(0.0, static_cast<double>(since_start.count()) * params_.update_rate_hz / 1e9);
  const double kf = std::floor(x);
  const double s = x - kf;
  const auto k = static_cast<std::int64_t>(kf);
  if (k < base_) restart();
  for (; base_ < k; ++base_) {
    prev_m_ = state_.p_m;
    step();
  }
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) out[i] = prev_m_[i] + s * (state_.p_m[i] - prev_m_[i]);
  return {out[0], out[1], out[2]};
}

}  // namespace gpsemu::noise
