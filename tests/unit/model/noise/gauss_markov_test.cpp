// The gauss-markov model, orders 1 and 2: sigma and tau recovered from long runs at 1 Hz and
// 10 Hz (it is defined in continuous time, so the rate must not change them), exact steps over
// any interval, determinism, validation.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "emulator/model/noise/noise_model.hpp"
#include "tests/support/noise_configs.hpp"
#include "tests/support/statistics.hpp"

namespace gpsemu::noise {
namespace {
namespace gauss_markov_test {

using std::chrono::milliseconds;

using test::autocorrelation;
using test::expect_throw_naming;
using test::gauss_markov;
using test::sd_of;

// 100 000 s of the process sampled at `rate_hz`: sigma from the standard deviation, tau from the
// autocorrelation at a 5 s lag (rho = exp(-5 / tau)), per axis.
void expect_recovered(double rate_hz) {
  const std::array<GaussMarkovAxis, 3> want{{{2.0, 30.0}, {0.5, 10.0}, {1.0, 120.0}}};
  auto model = make_noise_model(gauss_markov(want[0], want[1], want[2]), 17);
  const auto period_ns = static_cast<std::int64_t>(std::llround(1e9 / rate_hz));
  const std::size_t n = static_cast<std::size_t>(100000 * rate_hz);
  std::array<std::vector<double>, 3> x;
  for (auto& v : x) v.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Enu e = model->offset_at(std::chrono::nanoseconds(static_cast<std::int64_t>(k) * period_ns));
    x[0].push_back(e.east_m);
    x[1].push_back(e.north_m);
    x[2].push_back(e.up_m);
  }
  const auto lag = static_cast<std::size_t>(std::llround(5.0 * rate_hz));
  for (std::size_t i = 0; i < 3; ++i) {
    const double tau = -5.0 / std::log(autocorrelation(x[i], lag));
    // Relative standard errors: sd about sqrt(tau / T) (<= 3.5% for tau = 120 s), tau about
    // sqrt(2 tau / T) (<= 5%); the limits are about 2 standard errors.
    const double tol = want[i].tau_s > 100 ? 0.12 : 0.05;
    EXPECT_NEAR(sd_of(x[i]) / want[i].sigma_m, 1.0, tol) << "axis " << i << " at " << rate_hz << " Hz";
    EXPECT_NEAR(tau / want[i].tau_s, 1.0, 2 * tol) << "axis " << i << " at " << rate_hz << " Hz";
  }
  // The lag-one autocorrelation is exp(-dt / tau) at any rate.
  EXPECT_NEAR(autocorrelation(x[0], 1), std::exp(-1.0 / (rate_hz * 30.0)), 0.01 / rate_hz);
}

TEST(NoiseGaussMarkov, SigmaAndTauRecoveredAt1Hz) { expect_recovered(1.0); }
TEST(NoiseGaussMarkov, SigmaAndTauRecoveredAt10Hz) { expect_recovered(10.0); }

NoiseConfig order2(double sigma, double tau) {
  NoiseConfig c = gauss_markov({sigma, tau}, {sigma, tau}, {sigma, tau});
  c.gauss_markov_order = 2;
  return c;
}

// Order 2: the standard deviation, and the autocorrelation (1 + t/tau) exp(-t/tau) at t = tau
// (2/e) and t = tau/2, at 1 Hz and 10 Hz; its first difference is far smaller than order 1's.
void expect_order2(double rate_hz) {
  const double sigma = 1.5, tau = 20.0;
  auto model = make_noise_model(order2(sigma, tau), 23);
  const auto period_ns = static_cast<std::int64_t>(std::llround(1e9 / rate_hz));
  const std::size_t n = static_cast<std::size_t>(100000 * rate_hz);
  std::vector<double> x;
  x.reserve(n);
  for (std::size_t k = 0; k < n; ++k)
    x.push_back(model->offset_at(std::chrono::nanoseconds(static_cast<std::int64_t>(k) * period_ns)).north_m);
  EXPECT_NEAR(sd_of(x) / sigma, 1.0, 0.05) << rate_hz << " Hz";
  const auto lag = [&](double s) { return static_cast<std::size_t>(std::llround(s * rate_hz)); };
  EXPECT_NEAR(autocorrelation(x, lag(tau)), 2.0 / std::exp(1.0), 0.03) << rate_hz << " Hz";
  EXPECT_NEAR(autocorrelation(x, lag(tau / 2)), 1.5 / std::exp(0.5), 0.03) << rate_hz << " Hz";
  // Smooth: 1 - rho(dt) ~ (dt/tau)^2 / 2 instead of dt / tau.
  const double dt = 1.0 / rate_hz;
  EXPECT_NEAR(1.0 - autocorrelation(x, 1), 1.0 - (1.0 + dt / tau) * std::exp(-dt / tau),
              0.3 * (1.0 - (1.0 + dt / tau) * std::exp(-dt / tau)));
}

TEST(NoiseGaussMarkov, SecondOrderSigmaAndAutocorrelationAt1Hz) { expect_order2(1.0); }
TEST(NoiseGaussMarkov, SecondOrderSigmaAndAutocorrelationAt10Hz) { expect_order2(10.0); }

TEST(NoiseGaussMarkov, SecondOrderIsTheSameProcessWhateverTheQueryInterval) {
  // 1 s steps and 0.01 s steps must agree in distribution: compare the variance of the 1 s
  // change over a long run queried both ways.
  const NoiseConfig c = order2(1.0, 5.0);
  auto coarse = make_noise_model(c, 4), fine = make_noise_model(c, 5);
  double ss_coarse = 0.0, ss_fine = 0.0;
  double prev_c = coarse->offset_at(milliseconds(0)).east_m, prev_f = fine->offset_at(milliseconds(0)).east_m;
  const int n = 20000;
  for (int k = 1; k <= n; ++k) {
    const double xc = coarse->offset_at(milliseconds(1000 * k)).east_m;
    double xf = 0.0;
    for (int j = 1; j <= 100; ++j) xf = fine->offset_at(milliseconds(1000 * (k - 1) + 10 * j)).east_m;
    ss_coarse += (xc - prev_c) * (xc - prev_c);
    ss_fine += (xf - prev_f) * (xf - prev_f);
    prev_c = xc, prev_f = xf;
  }
  const double expected = 2.0 * (1.0 - 1.2 * std::exp(-0.2));  // 2 sigma^2 (1 - rho(1 s))
  EXPECT_NEAR(ss_coarse / n / expected, 1.0, 0.05);
  EXPECT_NEAR(ss_fine / n / expected, 1.0, 0.05);
}

TEST(NoiseGaussMarkov, ExactStepOverAnyInterval) {
  // One step over dt has variance sigma^2 (1 - phi^2) about phi x: check over 10 s jumps.
  auto model = make_noise_model(gauss_markov({1.0, 20.0}, {1.0, 20.0}, {1.0, 20.0}), 3);
  const double phi = std::exp(-10.0 / 20.0);
  double prev = model->offset_at(std::chrono::seconds(0)).east_m, ss = 0.0;
  const int n = 100000;
  for (int k = 1; k <= n; ++k) {
    const double x = model->offset_at(std::chrono::seconds(10 * k)).east_m;
    ss += (x - phi * prev) * (x - phi * prev);
    prev = x;
  }
  EXPECT_NEAR(std::sqrt(ss / n), std::sqrt(1.0 - phi * phi), 0.01);
}

TEST(NoiseGaussMarkov, SameTimeSameValueSameSeedSameSequence) {
  const NoiseConfig c = gauss_markov({1.0, 5.0}, {2.0, 5.0}, {3.0, 5.0});
  auto a = make_noise_model(c, 11), b = make_noise_model(c, 11), d = make_noise_model(c, 12);
  for (int k = 0; k < 100; ++k) {
    const Enu x = a->offset_at(milliseconds(250 * k));
    EXPECT_EQ(x.north_m, a->offset_at(milliseconds(250 * k)).north_m);
    EXPECT_EQ(x.north_m, b->offset_at(milliseconds(250 * k)).north_m);
    EXPECT_NE(x.north_m, d->offset_at(milliseconds(250 * k)).north_m);
  }
}

TEST(NoiseGaussMarkov, InvalidParametersThrowNamingThem) {
  const double inf = std::numeric_limits<double>::infinity();
  expect_throw_naming(gauss_markov({1, 1}, {-1, 1}, {1, 1}), "gauss-markov.north.sigma_m");
  expect_throw_naming(gauss_markov({1, 0}, {1, 1}, {1, 1}), "gauss-markov.east.tau_s");
  expect_throw_naming(gauss_markov({1, 1}, {1, 1}, {1, inf}), "gauss-markov.up.tau_s");
  NoiseConfig c = gauss_markov({1, 1}, {1, 1}, {1, 1});
  c.gauss_markov_order = 3;
  expect_throw_naming(c, "gauss-markov.order");
}

}  // namespace gauss_markov_test
}  // namespace
}  // namespace gpsemu::noise
