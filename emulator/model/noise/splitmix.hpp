// SplitMix64 (Steele, Lea & Flood 2014): the one 64-bit mixer and small generator every part uses
// for reproducible draws (the noise streams' seeds, the receiver clock's wander, garbled bytes):
// the same numbers on every platform, which std:: distributions do not promise. Header-only, so
// the protocol libraries use it without linking the noise models.
#pragma once

#include <cstdint>

namespace gpsemu::noise {

/// One SplitMix64 output for `state`: a bijective 64-bit mixer.
[[nodiscard]] constexpr std::uint64_t splitmix64(std::uint64_t state) {
  std::uint64_t z = state + 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// The generator: each next() is splitmix64 of the state, which then advances by the golden gamma.
struct SplitMix64 {
  std::uint64_t state = 0;
  constexpr std::uint64_t next() {
    const std::uint64_t z = splitmix64(state);
    state += 0x9E3779B97F4A7C15ULL;
    return z;
  }
  /// Uniform in [0, 1) with 53 random bits.
  constexpr double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

}  // namespace gpsemu::noise
