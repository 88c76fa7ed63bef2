// The `composite` noise model: what a real receiver's stationary error looks like on each axis,
//   smooth wander (second-order Gauss-Markov, or the cgrw walk)
//   + slow wander (second-order Gauss-Markov with a longer time constant; optional)
//   + white jitter (one independent normal draw per epoch)
//   + jumps (a Poisson process: at rate r a step of normal size sigma_j, each decaying back with
//     time constant T, or staying when T = 0: then the jumps add up as a random walk).
// Each part has its own random streams under the seed (smooth: streams 0-2 as its model alone;
// jitter 3-5; jumps 6-8; slow: streams 0-2 under stream_seed(seed, 9)), so the same seed and query times give the same values everywhere.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>

#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/noise/rng.hpp"

namespace gpsemu::noise {

/// Throws std::invalid_argument naming `composite.<axis>.<field>` unless every value is finite
/// and >= 0 (and the smooth gauss-markov component is valid).
void validate_composite(const CompositeParams& params);

class CompositeNoise final : public NoiseModel {
 public:
  /// `config.composite`, with `config.cgrw` as the smooth part when composite.smooth is cgrw.
  CompositeNoise(const NoiseConfig& config, std::uint64_t seed);

  /// smooth(t) + jitter + jumps(t). The jump process starts in its stationary distribution; a
  /// query earlier than the previous one starts every part again from its first draw.
  [[nodiscard]] Enu offset_at(std::chrono::nanoseconds since_start) override;

 private:
  void restart();
  void advance_jumps(std::size_t axis, double to_s);
  double next_wait_s(std::size_t axis);

  std::array<CompositeAxis, 3> axes_;
  std::unique_ptr<NoiseModel> smooth_;
  std::unique_ptr<NoiseModel> slow_;  // null when no axis has a slow part
  std::array<Rng, 3> jitter_rngs_, jump_rngs_;
  std::array<double, 3> jump_m_{};       // the jump process's offset at last_s_
  std::array<double, 3> next_jump_s_{};  // time of each axis's next jump
  double last_s_ = 0.0;
  bool started_ = false;
};

}  // namespace gpsemu::noise
