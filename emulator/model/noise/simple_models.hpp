// The two memoryless noise models: `gaussian` (independent white noise per axis, one fresh draw
// per query, i.e. per epoch) and `none` (zero).
#pragma once

#include <array>
#include <cstdint>

#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/noise/rng.hpp"

namespace gpsemu::noise {

/// Throws std::invalid_argument naming `gaussian.<axis>.<field>` unless every mean is finite and
/// every sigma is finite and >= 0.
void validate_gaussian_axes(const std::array<GaussianAxis, 3>& axes);

class GaussianNoise final : public NoiseModel {
 public:
  /// Axis i (east 0, north 1, up 2) draws from Rng(seed, i).
  GaussianNoise(const std::array<GaussianAxis, 3>& axes, std::uint64_t seed);
  /// mean_m + sigma_m * N(0, 1) per axis; the time is ignored (one draw per call).
  [[nodiscard]] Enu offset_at(std::chrono::nanoseconds since_start) override;

 private:
  std::array<GaussianAxis, 3> axes_;
  std::array<Rng, 3> rngs_;
};

class NoNoise final : public NoiseModel {
 public:
  [[nodiscard]] Enu offset_at(std::chrono::nanoseconds /*since_start*/) override { return {}; }
};

}  // namespace gpsemu::noise
