#include "emulator/model/noise/rng.hpp"

#include <array>
#include <cmath>

namespace gpsemu::noise {
namespace {

/// The ziggurat's 128 layers of equal area under exp(-x^2/2): x[i] is layer i's right edge
/// (x[0] the base's pseudo-edge that gives it the same area, tail included; x[128] = 0) and
/// ratio[i] = x[i+1] / x[i], the share of layer i that lies wholly under the curve.
struct Ziggurat {
  static constexpr int kLayers = 128;
  static constexpr double kTailStart = 3.442619855899;        // x[1]
  static constexpr double kLayerArea = 9.91256303526217e-3;   // of each layer, tail included
  std::array<double, kLayers + 1> x{};
  std::array<double, kLayers> ratio{};
  Ziggurat() {
    double f = std::exp(-0.5 * kTailStart * kTailStart);
    x[0] = kLayerArea / f;
    x[1] = kTailStart;
    x[kLayers] = 0.0;
    for (int i = 2; i < kLayers; ++i) {
      x[i] = std::sqrt(-2.0 * std::log(kLayerArea / x[i - 1] + f));
      f = std::exp(-0.5 * x[i] * x[i]);
    }
    for (int i = 0; i < kLayers; ++i) ratio[i] = x[i + 1] / x[i];
  }
};

const Ziggurat& ziggurat() {
  static const Ziggurat z;
  return z;
}

}  // namespace

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

double Rng::ziggurat_normal() {
  const Ziggurat& z = ziggurat();
  for (;;) {
    // One output: its low 7 bits choose the layer, its top 53 the signed position in it.
    const std::uint64_t r = engine_();
    const int i = static_cast<int>(r & (Ziggurat::kLayers - 1));
    const double u = 2.0 * (static_cast<double>(r >> 11) * 0x1.0p-53) - 1.0;
    if (std::fabs(u) < z.ratio[i]) return u * z.x[i];  // wholly under the curve
    if (i == 0) {
      // The tail beyond x[1] (Marsaglia's method): exponential proposals, accepted under the curve.
      double t = 0.0;
      double y = 0.0;
      do {
        t = std::log(1.0 - uniform()) / Ziggurat::kTailStart;  // <= 0
        y = std::log(1.0 - uniform());
      } while (-2.0 * y < t * t);
      return u < 0.0 ? t - Ziggurat::kTailStart : Ziggurat::kTailStart - t;
    }
    // The wedge between the layer's inner and outer edge: accept under the curve.
    const double v = u * z.x[i];
    const double f0 = std::exp(-0.5 * (z.x[i] * z.x[i] - v * v));
    const double f1 = std::exp(-0.5 * (z.x[i + 1] * z.x[i + 1] - v * v));
    if (f1 + uniform() * (f0 - f1) < 1.0) return v;
  }
}

}  // namespace gpsemu::noise
