// The `gauss-markov` noise model: a Gauss-Markov process per axis (the GPS error model of PX4's
// and Gazebo's simulators), stationary standard deviation sigma and correlation time tau, of
// order 1 (the default) or 2:
//   order 1: dx = -x / tau dt + sigma sqrt(2 / tau) dW;    autocorrelation exp(-|t| / tau)
//   order 2: critically damped, x follows a first-order process y through the same time
//            constant: dy = -y / tau dt + q dW, dx = (y - x) / tau dt, q^2 = 4 sigma^2 / tau;
//            autocorrelation (1 + |t| / tau) exp(-|t| / tau). Its path is smooth (its velocity is
//            a process, not white noise), as a receiver's filtered position is: over a log
//            shorter than a few tau, order 1 cannot be both as wide and as smooth as real
//            receivers (first-difference variance >= about 6 / N x the sample variance of N
//            samples), order 2 can.
// Both are defined in continuous time and sampled with the exact discretisation for whatever
// interval separates two queries (order 1: x' = phi x + sigma sqrt(1 - phi^2) N(0, 1),
// phi = exp(-dt / tau); order 2: the 2x2 transition matrix and process-noise covariance in
// closed form), so the output rate does not change the statistics.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>

#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/noise/rng.hpp"

namespace gpsemu::noise {

/// Throws std::invalid_argument naming `gauss-markov.<axis>.<field>` unless every sigma_m is
/// finite and >= 0 and every tau_s is finite and > 0, or `gauss-markov.order` unless 1 or 2.
void validate_gauss_markov_axes(const std::array<GaussMarkovAxis, 3>& axes, int order = 1);

/// Autocorrelation of the process of `order` at lag `lag_s` for correlation time `tau_s`.
[[nodiscard]] double gauss_markov_autocorrelation(int order, double lag_s, double tau_s);

class GaussMarkovNoise final : public NoiseModel {
 public:
  /// Axis i (east 0, north 1, up 2) draws from Rng(seed, i).
  GaussMarkovNoise(const std::array<GaussMarkovAxis, 3>& axes, std::uint64_t seed, int order = 1);

  /// The process at `since_start`. The first query draws from the stationary distribution; each
  /// later one steps exactly over the time since the previous query (the same time again gives
  /// the same value). A query earlier than the previous one starts the process again from its
  /// first draw.
  [[nodiscard]] Enu offset_at(std::chrono::nanoseconds since_start) override;

 private:
  void restart();
  void step(std::size_t axis, double dt_s);

  std::array<GaussMarkovAxis, 3> axes_;
  int order_;
  std::array<Rng, 3> rngs_;
  std::array<double, 3> x_m_{};  // position error
  std::array<double, 3> y_m_{};  // order 2: the driving first-order process
  std::chrono::nanoseconds last_{0};
  bool started_ = false;
};

}  // namespace gpsemu::noise
