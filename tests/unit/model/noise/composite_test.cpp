// The composite model: smooth wander + white jitter + jumps. Deterministic given the seed; each
// component has the variance it is configured with; jumps decay back with their time constant.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "emulator/model/noise/composite_model.hpp"

namespace gpsemu::noise {
namespace {
namespace composite_test {

NoiseConfig composite(double smooth_sigma, double jitter, double rate, double jump, double decay) {
  NoiseConfig c;
  c.model = Model::composite;
  for (std::size_t a = 0; a < 3; ++a) {
    c.composite.smooth_gm[a] = {smooth_sigma, 30.0};
    c.composite.axes[a] = {jitter, rate, jump, decay};
  }
  return c;
}

std::vector<double> east(const NoiseConfig& c, std::uint64_t seed, int n, double rate_hz) {
  auto m = make_noise_model(c, seed);
  std::vector<double> x;
  for (int k = 0; k < n; ++k)
    x.push_back(m->offset_at(std::chrono::nanoseconds(std::llround(k * 1e9 / rate_hz))).east_m);
  return x;
}

double variance(const std::vector<double>& x) {
  double m = 0, v = 0;
  for (double e : x) m += e / static_cast<double>(x.size());
  for (double e : x) v += (e - m) * (e - m) / static_cast<double>(x.size());
  return v;
}

TEST(Composite, SameSeedSameValuesOtherSeedOthers) {
  const NoiseConfig c = composite(0.3, 0.05, 0.02, 0.4, 20.0);
  EXPECT_EQ(east(c, 5, 500, 5.0), east(c, 5, 500, 5.0));
  EXPECT_NE(east(c, 5, 500, 5.0), east(c, 6, 500, 5.0));
}

TEST(Composite, JitterAloneIsWhiteWithItsSigma) {
  const auto x = east(composite(0.0, 0.2, 0.0, 0.0, 0.0), 1, 20000, 1.0);
  EXPECT_NEAR(std::sqrt(variance(x)), 0.2, 0.006);
  std::vector<double> d1;
  for (std::size_t k = 1; k < x.size(); ++k) d1.push_back(x[k] - x[k - 1]);
  EXPECT_NEAR(std::sqrt(variance(d1)), 0.2 * std::sqrt(2.0), 0.01);
}

TEST(Composite, DecayingJumpsHaveCampbellsVariance) {
  // rate 0.05/s, size 1 m, decay 20 s: variance 0.05 x 1 x 20 / 2 = 0.5 m^2.
  const auto x = east(composite(0.0, 0.0, 0.05, 1.0, 20.0), 2, 200000, 1.0);
  EXPECT_NEAR(variance(x), 0.5, 0.05);
}

TEST(Composite, JumpsAreStepsBetweenEpochs) {
  // Without decay and without other parts, the path is piecewise constant: most differences are
  // exactly 0, the others are jumps.
  const auto x = east(composite(0.0, 0.0, 0.01, 1.0, 0.0), 3, 10000, 1.0);
  int steps = 0;
  for (std::size_t k = 1; k < x.size(); ++k) steps += x[k] != x[k - 1];
  EXPECT_GT(steps, 70);
  EXPECT_LT(steps, 130);
}

TEST(Composite, BadParametersAreNamed) {
  NoiseConfig c = composite(0.3, 0.05, 0.02, 0.4, 20.0);
  c.composite.axes[1].jump_rate_hz = -1.0;
  try {
    (void)make_noise_model(c, 1);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("composite.north.jump_rate_hz"), std::string::npos) << e.what();
  }
}

TEST(Composite, WithoutJitterAndJumpsIsItsSmoothPartExactly) {
  NoiseConfig gm;
  gm.model = Model::gauss_markov;
  gm.gauss_markov_order = 2;
  gm.gauss_markov = {{{0.3, 30.0}, {0.3, 30.0}, {0.3, 30.0}}};
  EXPECT_EQ(east(composite(0.3, 0.0, 0.0, 0.0, 0.0), 9, 1000, 5.0), east(gm, 9, 1000, 5.0));
}

TEST(Composite, NameParsesBothWays) {
  EXPECT_EQ(parse_model("composite"), Model::composite);
  EXPECT_EQ(to_string(Model::composite), "composite");
}

// The slow part (issue 27): a second-order Gauss-Markov added to the rest, its own streams (the
// rest is unchanged by it), its variance added, its correlation kept at lags where the smooth
// part's is gone, and bounded however long the run.
TEST(Composite, SlowPartAddsItsVarianceAndLongCorrelation) {
  NoiseConfig fast = composite(0.2, 0.0, 0.0, 0.0, 0.0);
  for (auto& g : fast.composite.smooth_gm) g.tau_s = 3.0;
  NoiseConfig slow = fast;
  for (auto& a : slow.composite.axes) a.slow_sigma_m = 0.5, a.slow_tau_s = 100.0;
  const int n = 200000;
  const std::vector<double> xf = east(fast, 11, n, 1.0), xs = east(slow, 11, n, 1.0);
  EXPECT_NEAR(variance(xs), 0.2 * 0.2 + 0.5 * 0.5, 0.05 * (0.2 * 0.2 + 0.5 * 0.5));
  // The difference of the two is the slow process alone: the rest drew the same numbers.
  std::vector<double> d;
  for (int k = 0; k < n; ++k) d.push_back(xs[k] - xf[k]);
  EXPECT_NEAR(std::sqrt(variance(d)), 0.5, 0.05);
  double c30 = 0, m = 0;
  for (double v : d) m += v / n;
  for (int k = 30; k < n; ++k) c30 += (d[k] - m) * (d[k - 30] - m) / (n - 30);
  EXPECT_NEAR(c30 / variance(d), (1.0 + 30.0 / 100.0) * std::exp(-30.0 / 100.0), 0.05);
  // Bounded: no sample of 200 000 s (2000 time constants) beyond 6 sigma of the whole.
  for (double v : xs) ASSERT_LT(std::abs(v), 6.0 * std::sqrt(0.2 * 0.2 + 0.5 * 0.5));
}

TEST(Composite, SlowPartNeedsATimeConstant) {
  NoiseConfig c = composite(0.2, 0.0, 0.0, 0.0, 0.0);
  c.composite.axes[1].slow_sigma_m = 0.5;
  try {
    (void)make_noise_model(c, 1);
    FAIL() << "a slow part without a time constant was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("composite.north.slow_tau_s"), std::string::npos) << e.what();
  }
}

}  // namespace composite_test
}  // namespace
}  // namespace gpsemu::noise
