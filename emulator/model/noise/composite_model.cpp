#include "emulator/model/noise/composite_model.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "emulator/model/noise/cgrw_model.hpp"
#include "emulator/model/noise/gauss_markov_model.hpp"

namespace gpsemu::noise {
namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();

std::unique_ptr<NoiseModel> make_smooth(const NoiseConfig& config, std::uint64_t seed) {
  if (config.composite.smooth == CompositeSmooth::cgrw) {
    CgrwParams walk = config.cgrw;
    if (const auto& axes = config.composite.smooth_cgrw) walk.east = (*axes)[0], walk.north = (*axes)[1], walk.up = (*axes)[2];
    return std::make_unique<CgrwNoise>(walk, seed);
  }
  return std::make_unique<GaussMarkovNoise>(config.composite.smooth_gm, seed, 2);
}

std::unique_ptr<NoiseModel> make_slow(const CompositeParams& p, std::uint64_t seed) {
  std::array<GaussMarkovAxis, 3> axes{};
  bool any = false;
  for (std::size_t i = 0; i < 3; ++i) {
    const bool on = p.axes[i].slow_sigma_m > 0.0;
    axes[i] = {on ? p.axes[i].slow_sigma_m : 0.0, on ? p.axes[i].slow_tau_s : 1.0};
    any = any || on;
  }
  if (!any) return nullptr;
  return std::make_unique<GaussMarkovNoise>(axes, stream_seed(seed, 9), 2);
}

}  // namespace

void validate_composite(const CompositeParams& p) {
  const char* names[] = {"east", "north", "up"};
  for (std::size_t i = 0; i < 3; ++i) {
    const CompositeAxis& a = p.axes[i];
    const std::pair<const char*, double> fields[] = {{"jitter_sigma_m", a.jitter_sigma_m},
                                                      {"jump_rate_hz", a.jump_rate_hz},
                                                      {"jump_sigma_m", a.jump_sigma_m},
                                                      {"jump_decay_s", a.jump_decay_s},
                                                      {"slow_sigma_m", a.slow_sigma_m},
                                                      {"slow_tau_s", a.slow_tau_s}};
    for (const auto& [field, value] : fields) {
      if (value >= 0.0 && std::isfinite(value)) continue;
      std::ostringstream os;
      os << "composite." << names[i] << "." << field << " must be finite and >= 0 (got " << value << ")";
      throw std::invalid_argument(os.str());
    }
    if (a.slow_sigma_m > 0.0 && !(a.slow_tau_s > 0.0)) {
      std::ostringstream os;
      os << "composite." << names[i] << ".slow_tau_s must be > 0 when slow_sigma_m is (got " << a.slow_tau_s << ")";
      throw std::invalid_argument(os.str());
    }
  }
  if (p.smooth == CompositeSmooth::gauss_markov_2) validate_gauss_markov_axes(p.smooth_gm, 2);
}

CompositeNoise::CompositeNoise(const NoiseConfig& config, std::uint64_t seed)
    : axes_(config.composite.axes),
      smooth_((validate_composite(config.composite), make_smooth(config, seed))),
      slow_(make_slow(config.composite, seed)),
      jitter_rngs_{Rng(seed, 3), Rng(seed, 4), Rng(seed, 5)},
      jump_rngs_{Rng(seed, 6), Rng(seed, 7), Rng(seed, 8)} {}

double CompositeNoise::next_wait_s(std::size_t i) {
  const double rate = axes_[i].jump_rate_hz;
  if (!(rate > 0.0)) return kNever;
  return -std::log1p(-jump_rngs_[i].uniform()) / rate;  // exponential waiting time
}

void CompositeNoise::restart() {
  for (std::size_t i = 0; i < 3; ++i) {
    jitter_rngs_[i].reset();
    jump_rngs_[i].reset();
    const CompositeAxis& a = axes_[i];
    // Stationary variance of decaying jumps (Campbell's theorem): rate sigma^2 T / 2.
    const double var = a.jump_decay_s > 0.0 ? a.jump_rate_hz * a.jump_sigma_m * a.jump_sigma_m * a.jump_decay_s / 2.0 : 0.0;
    jump_m_[i] = std::sqrt(var) * jump_rngs_[i].normal();
    next_jump_s_[i] = next_wait_s(i);
  }
  last_s_ = 0.0;
  started_ = true;
}

void CompositeNoise::advance_jumps(std::size_t i, double to_s) {
  const CompositeAxis& a = axes_[i];
  double at = last_s_;
  const auto decay = [&](double until) {
    if (a.jump_decay_s > 0.0) jump_m_[i] *= std::exp(-(until - at) / a.jump_decay_s);
    at = until;
  };
  while (next_jump_s_[i] <= to_s) {
    decay(next_jump_s_[i]);
    jump_m_[i] += a.jump_sigma_m * jump_rngs_[i].normal();
    next_jump_s_[i] += next_wait_s(i);
  }
  decay(to_s);
}

Enu CompositeNoise::offset_at(std::chrono::nanoseconds since_start) {
  const double t_s = static_cast<double>(since_start.count()) / 1e9;
  if (!started_ || t_s < last_s_) restart();
  const Enu smooth = smooth_->offset_at(since_start);
  std::array<double, 3> out{smooth.east_m, smooth.north_m, smooth.up_m};
  if (slow_) {
    const Enu slow = slow_->offset_at(since_start);
    out[0] += slow.east_m, out[1] += slow.north_m, out[2] += slow.up_m;
  }
  for (std::size_t i = 0; i < 3; ++i) {
    advance_jumps(i, t_s);
    out[i] += jump_m_[i] + axes_[i].jitter_sigma_m * jitter_rngs_[i].normal();
  }
  last_s_ = t_s;
  return {out[0], out[1], out[2]};
}

}  // namespace gpsemu::noise
