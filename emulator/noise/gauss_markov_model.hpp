// The `gauss-markov` noise model: a first-order Gauss-Markov process per axis (the GPS error
// model of PX4's and Gazebo's simulators), dx = -x / tau dt + sigma sqrt(2 / tau) dW, stationary
// standard deviation sigma and autocorrelation exp(-|dt| / tau). Defined in continuous time and
// sampled with the exact discretisation for whatever interval separates two queries:
//   phi = exp(-dt / tau);   x' = phi x + sigma sqrt(1 - phi^2) N(0, 1)
// so the output rate does not change its statistics (it is not a per-step filter whose
// correlation depends on the step, as a discrete x' = a x + b w tuned at one rate would be).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>

#include "emulator/noise/noise_model.hpp"
#include "emulator/noise/rng.hpp"

namespace gpsemu::noise {

/// Throws std::invalid_argument naming `gauss-markov.<axis>.<field>` unless every sigma_m is
/// finite and >= 0 and every tau_s is finite and > 0.
void validate_gauss_markov_axes(const std::array<GaussMarkovAxis, 3>& axes);

class GaussMarkovNoise final : public NoiseModel {
 public:
  /// Axis i (east 0, north 1, up 2) draws from Rng(seed, i).
  GaussMarkovNoise(const std::array<GaussMarkovAxis, 3>& axes, std::uint64_t seed);

  /// The process at `since_start`. The first query draws from the stationary distribution
  /// N(0, sigma); each later one steps exactly over the time since the previous query (the same
  /// time again gives the same value). A query earlier than the previous one starts the process
  /// again from its first draw.
  [[nodiscard]] Enu offset_at(std::chrono::nanoseconds since_start) override;

 private:
  void restart();

  std::array<GaussMarkovAxis, 3> axes_;
  std::array<Rng, 3> rngs_;
  std::array<double, 3> x_m_{};
  std::chrono::nanoseconds last_{0};
  bool started_ = false;
};

}  // namespace gpsemu::noise
