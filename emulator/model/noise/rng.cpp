#include "emulator/model/noise/rng.hpp"

#include <cmath>

namespace gpsemu::noise {

std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream) {
  // Mix the seed first so that (seed, stream) pairs do not collide by simple arithmetic.
  return splitmix64(splitmix64(seed) ^ splitmix64(~stream));
}

Rng::Rng(std::uint64_t seed, std::uint64_t stream)
    : engine_seed_(stream_seed(seed, stream)), engine_(engine_seed_) {}

void Rng::reset() {
  engine_.seed(engine_seed_);
  spare_ = 0.0;
  has_spare_ = false;
}

double Rng::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u = 0.0;
  double v = 0.0;
  double s = 0.0;
  do {
    u = 2.0 * uniform() - 1.0;
    v = 2.0 * uniform() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double factor = std::sqrt(-2.0 * std::log(s) / s);
  spare_ = v * factor;
  has_spare_ = true;
  return u * factor;
}

}  // namespace gpsemu::noise
