#include "emulator/noise/gauss_markov_model.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace gpsemu::noise {

void validate_gauss_markov_axes(const std::array<GaussMarkovAxis, 3>& axes) {
  const char* names[] = {"east", "north", "up"};
  for (std::size_t i = 0; i < 3; ++i) {
    std::ostringstream os;
    if (!(axes[i].sigma_m >= 0.0) || !std::isfinite(axes[i].sigma_m)) {
      os << "gauss-markov." << names[i] << ".sigma_m must be finite and >= 0 (got "
         << axes[i].sigma_m << ")";
    } else if (!(axes[i].tau_s > 0.0) || !std::isfinite(axes[i].tau_s)) {
      os << "gauss-markov." << names[i] << ".tau_s must be finite and > 0 seconds (got "
         << axes[i].tau_s << ")";
    }
    if (!os.str().empty()) throw std::invalid_argument(os.str());
  }
}

GaussMarkovNoise::GaussMarkovNoise(const std::array<GaussMarkovAxis, 3>& axes, std::uint64_t seed)
    : axes_(axes), rngs_{Rng(seed, 0), Rng(seed, 1), Rng(seed, 2)} {
  validate_gauss_markov_axes(axes_);
}

void GaussMarkovNoise::restart() {
  for (std::size_t i = 0; i < 3; ++i) {
    rngs_[i].reset();
    x_m_[i] = axes_[i].sigma_m * rngs_[i].normal();
  }
  started_ = true;
}

Enu GaussMarkovNoise::offset_at(std::chrono::nanoseconds since_start) {
  if (!started_ || since_start < last_) {
    restart();
  } else if (since_start > last_) {
    const double dt_s = static_cast<double>((since_start - last_).count()) / 1e9;
    for (std::size_t i = 0; i < 3; ++i) {
      const double phi = std::exp(-dt_s / axes_[i].tau_s);
      const double innovation = std::sqrt(-std::expm1(-2.0 * dt_s / axes_[i].tau_s));
      x_m_[i] = phi * x_m_[i] + axes_[i].sigma_m * innovation * rngs_[i].normal();
    }
  }
  last_ = since_start;
  return {x_m_[0], x_m_[1], x_m_[2]};
}

}  // namespace gpsemu::noise
