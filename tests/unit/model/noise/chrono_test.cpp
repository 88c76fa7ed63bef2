// The chrono model: Project Chrono 9's ChNoiseRandomWalks arithmetic step by step against a
// hand-written reference with the same draws, its evaluation between steps, and its bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "emulator/model/noise/chrono_model.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/noise/rng.hpp"
#include "tests/support/noise_configs.hpp"

namespace gpsemu::noise {
namespace {
namespace chrono_test {

using std::chrono::milliseconds;

using test::chrono;
using test::expect_throw_naming;

// Chrono's AddNoise loop written out for one full step, with the draws taken from the model's
// documented stream (Rng(seed, 0): east, north, up per step).
struct Reference {
  double sigma, dt, vmax, amax;
  std::array<double, 3> p{}, v{};
  int accel_clamps = 0, speed_clamps = 0;
  void step(Rng& rng) {
    std::array<double, 3> a{};
    for (int i = 0; i < 3; ++i) {
      const double mean = -0.2 * sigma * p[i];  // m_sigma * 0.2 * (-1) * p / maxD, maxD = 1
      a[i] = mean + sigma * rng.normal();
      if (a[i] > amax) a[i] = amax, ++accel_clamps;
      if (a[i] < -amax) a[i] = -amax, ++accel_clamps;
    }
    for (int i = 0; i < 3; ++i) v[i] += a[i] * dt;
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > vmax) {
      for (double& x : v) x = x / len * vmax;
      ++speed_clamps;
    }
    for (int i = 0; i < 3; ++i) p[i] += v[i] * dt;
  }
};

TEST(NoiseChrono, StepsMatchChronosArithmeticWithTheSameDraws) {
  // Large sigma against the clamps so both the per-axis acceleration clamp and the 3-D velocity
  // rescale act within the first steps; mean 0.7 is ignored as in Chrono 9.
  auto model = make_noise_model(chrono(0.7, 0.5, 10.0, 0.02, 0.3), 42);
  Reference ref{0.5, 0.1, 0.02, 0.3};
  Rng rng(42, 0);
  ref.step(rng);  // the position at t = 0.1 s
  // First step by hand: p = 0 so the mean is 0; v = clamp(0.5 z) * 0.1; p = v * 0.1.
  {
    Rng r(42, 0);
    std::array<double, 3> v{};
    for (double& x : v) x = std::clamp(0.5 * r.normal(), -0.3, 0.3) * 0.1;
    const double len = std::hypot(v[0], v[1], v[2]);
    const double k = len > 0.02 ? 0.02 / len : 1.0;
    const Enu x = model->offset_at(milliseconds(100));
    EXPECT_DOUBLE_EQ(x.east_m, v[0] * k * 0.1);
    EXPECT_DOUBLE_EQ(x.north_m, v[1] * k * 0.1);
    EXPECT_DOUBLE_EQ(x.up_m, v[2] * k * 0.1);
  }
  EXPECT_EQ(model->offset_at(milliseconds(0)).east_m, 0.0);  // at rest at zero at the start
  for (int k = 1; k <= 200; ++k) {
    const Enu x = model->offset_at(milliseconds(100 * k));
    ASSERT_DOUBLE_EQ(x.east_m, ref.p[0]) << "step " << k;
    ASSERT_DOUBLE_EQ(x.north_m, ref.p[1]) << "step " << k;
    ASSERT_DOUBLE_EQ(x.up_m, ref.p[2]) << "step " << k;
    ref.step(rng);
  }
  EXPECT_GT(ref.accel_clamps, 10);
  EXPECT_GT(ref.speed_clamps, 10);
}

TEST(NoiseChrono, LinearBetweenStepsAndIndependentOfTheQueryRate) {
  const NoiseConfig c = chrono(0, 0.047, 100.0, 0.016, 0.152);  // the ART/IROS demo
  auto fine = make_noise_model(c, 7);
  auto coarse = make_noise_model(c, 7);
  for (int ms = 0; ms <= 20000; ms += 5) {
    const Enu f = fine->offset_at(milliseconds(ms));
    if (ms % 1000 == 0) {
      const Enu g = coarse->offset_at(milliseconds(ms));
      EXPECT_EQ(f.east_m, g.east_m);
      EXPECT_EQ(f.up_m, g.up_m);
    }
  }
  auto model = make_noise_model(c, 7);
  const Enu a = model->offset_at(milliseconds(120)), b = model->offset_at(milliseconds(130));
  auto again = make_noise_model(c, 7);
  const Enu mid = again->offset_at(milliseconds(125));
  EXPECT_NEAR(mid.north_m, 0.5 * (a.north_m + b.north_m), 1e-15);
}

TEST(NoiseChrono, VelocityBoundHoldsAtTheDemoParameters) {
  auto model = make_noise_model(chrono(0, 0.0163, 1.0, 0.03, 0.005), 3);  // defaults, 1 Hz
  Enu prev = model->offset_at(milliseconds(0));
  double max_step = 0.0, max_abs = 0.0;
  for (int s = 1; s <= 3600; ++s) {
    const Enu x = model->offset_at(std::chrono::seconds(s));
    const Enu d = x - prev;
    max_step = std::max(max_step, std::sqrt(d.east_m * d.east_m + d.north_m * d.north_m + d.up_m * d.up_m));
    max_abs = std::max(max_abs, std::abs(x.east_m));
    prev = x;
  }
  EXPECT_LE(max_step, 0.03 + 1e-12);  // |v| <= v_max and dt = 1 s
  EXPECT_GT(max_step, 0.02);          // and it does reach it
  EXPECT_GT(max_abs, 0.1);            // it wanders
}

TEST(NoiseChrono, EarlierQueryReplaysAndSeedsDiffer) {
  const NoiseConfig c = chrono(0, 0.0163, 1.0, 0.03, 0.005);
  auto a = make_noise_model(c, 5);
  const double at50 = a->offset_at(std::chrono::seconds(50)).east_m;
  (void)a->offset_at(std::chrono::seconds(80));
  EXPECT_EQ(a->offset_at(std::chrono::seconds(50)).east_m, at50);
  auto b = make_noise_model(c, 6);
  EXPECT_NE(b->offset_at(std::chrono::seconds(50)).east_m, at50);
}

TEST(NoiseChrono, InvalidParametersThrowNamingThem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_throw_naming(chrono(0, -1, 1, 0.03, 0.005), "chrono.sigma");
  expect_throw_naming(chrono(0, 1, 0, 0.03, 0.005), "chrono.update_rate_hz");
  expect_throw_naming(chrono(0, 1, 1, nan, 0.005), "chrono.v_max_mps");
  expect_throw_naming(chrono(0, 1, 1, 0.03, -1), "chrono.a_max_mps2");
  expect_throw_naming(chrono(nan, 1, 1, 0.03, 0.005), "chrono.mean");
}

}  // namespace chrono_test
}  // namespace
}  // namespace gpsemu::noise
