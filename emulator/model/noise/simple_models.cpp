#include "emulator/model/noise/simple_models.hpp"

#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "emulator/model/noise/cgrw_model.hpp"
#include "emulator/model/noise/chrono_model.hpp"
#include "emulator/model/noise/composite_model.hpp"
#include "emulator/model/noise/gauss_markov_model.hpp"

namespace gpsemu::noise {

void validate_gaussian_axes(const std::array<GaussianAxis, 3>& axes) {
  const char* names[] = {"east", "north", "up"};
  for (std::size_t i = 0; i < 3; ++i) {
    std::ostringstream os;
    if (!std::isfinite(axes[i].mean_m)) {
      os << "gaussian." << names[i] << ".mean_m must be finite (got " << axes[i].mean_m << ")";
    } else if (!(axes[i].sigma_m >= 0.0) || !std::isfinite(axes[i].sigma_m)) {
      os << "gaussian." << names[i] << ".sigma_m must be finite and >= 0 (got "
         << axes[i].sigma_m << ")";
    }
    if (!os.str().empty()) throw std::invalid_argument(os.str());
  }
}

GaussianNoise::GaussianNoise(const std::array<GaussianAxis, 3>& axes, std::uint64_t seed)
    : axes_(axes), rngs_{Rng(seed, 0), Rng(seed, 1), Rng(seed, 2)} {
  validate_gaussian_axes(axes_);
}

Enu GaussianNoise::offset_at(std::chrono::nanoseconds /*since_start*/) {
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) out[i] = axes_[i].mean_m + axes_[i].sigma_m * rngs_[i].normal();
  return {out[0], out[1], out[2]};
}

std::unique_ptr<NoiseModel> make_noise_model(const NoiseConfig& config, std::uint64_t seed) {
  switch (config.model) {
    case Model::none: return std::make_unique<NoNoise>();
    case Model::gaussian: return std::make_unique<GaussianNoise>(config.gaussian, seed);
    case Model::cgrw: return std::make_unique<CgrwNoise>(config.cgrw, seed);
    case Model::chrono: return std::make_unique<ChronoNoise>(config.chrono, seed);
    case Model::gauss_markov: return std::make_unique<GaussMarkovNoise>(config.gauss_markov, seed,
                                                                           config.gauss_markov_order);
    case Model::composite: return std::make_unique<CompositeNoise>(config, seed);
  }
  throw std::invalid_argument("noise model: unknown value " +
                              std::to_string(static_cast<int>(config.model)));
}

}  // namespace gpsemu::noise
