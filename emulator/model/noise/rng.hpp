// Deterministic random numbers for the noise models: the same seed and stream give the same
// sequence on every platform (std::mt19937_64 is fully specified by the standard; the uniform and
// normal transforms are written out here instead of using the implementation-defined
// std::*_distribution). The one remaining platform dependency is std::log/std::sqrt in the normal
// transform: bit-identical wherever they are correctly rounded for the arguments met and the
// compiler does not contract a*b+c into fused multiply-adds (-ffp-contract=off).
#pragma once

#include <cstdint>
#include <random>

#include "emulator/model/noise/splitmix.hpp"

namespace gpsemu::noise {


/// The engine seed of stream `stream` under the user's `seed` (SplitMix64 of both, so nearby
/// seeds and streams give unrelated engines).
[[nodiscard]] std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream);

/// A std::mt19937_64 seeded with stream_seed(seed, stream), with portable uniform and normal
/// transforms. Does not allocate; copying it copies the position in the sequence.
class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t stream);

  /// Back to the first number of the sequence.
  void reset();
  /// The engine's next raw 64-bit output.
  [[nodiscard]] std::uint64_t next_u64() { return engine_(); }
  /// Uniform in [0, 1) with 53 random bits (every double k / 2^53).
  [[nodiscard]] double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Standard normal (mean 0, standard deviation 1), Marsaglia's polar method.
  [[nodiscard]] double normal();
  /// Standard normal by Marsaglia and Tsang's ziggurat (128 layers, in Doornik's form): one engine
  /// output, a table look-up and a multiply for about 99 % of draws, no logarithm; a different
  /// sequence from normal() of the same stream. For streams that draw several normals an epoch.
  [[nodiscard]] double ziggurat_normal();

 private:
  std::uint64_t engine_seed_;
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace gpsemu::noise
