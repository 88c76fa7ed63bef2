// The velocity error model (emulator/model/noise/velocity_noise.hpp): white plus a first-order
// Gauss-Markov part per axis, its statistics whatever the epoch rate, deterministic given the seed,
// and its parameters' ranges.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "emulator/model/noise/velocity_noise.hpp"

namespace gpsemu::noise {
namespace {

using std::chrono::milliseconds;

struct AxisStats {
  double sd_east = 0, sd_up = 0, lag_corr_east = 0;
};

/// The east and up standard deviations and the east autocorrelation at a lag of `lag` samples,
/// over `n` samples every `step`.
AxisStats stats_of(const VelocityNoiseParams& p, std::uint64_t seed, milliseconds step, int n, int lag) {
  VelocityNoise v(p, seed);
  std::vector<double> east, up;
  for (int k = 0; k < n; ++k) {
    const Enu e = v.error_at(step * k);
    east.push_back(e.east_m);
    up.push_back(e.up_m);
  }
  const auto sd = [](const std::vector<double>& x) {
    double s = 0, ss = 0;
    for (double a : x) s += a, ss += a * a;
    const double m = s / x.size();
    return std::sqrt(ss / x.size() - m * m);
  };
  double c = 0, v0 = 0;
  for (std::size_t k = 0; k + lag < east.size(); ++k) c += east[k] * east[k + lag];
  for (double a : east) v0 += a * a;
  return {sd(east), sd(up), (c / (east.size() - lag)) / (v0 / east.size())};
}

TEST(VelocityNoise, EachAxisScattersByTheRootSumOfBothPartsAndUpByTheRatio) {
  VelocityNoiseParams p;  // 0.03 white, 0.02 wander over 10 s, up x 1.6
  const AxisStats s = stats_of(p, 7, milliseconds{1000}, 200000, 1);
  EXPECT_NEAR(s.sd_east, p.horizontal_sigma_mps(), 0.05 * p.horizontal_sigma_mps());
  EXPECT_NEAR(s.sd_up, 1.6 * p.horizontal_sigma_mps(), 0.05 * 1.6 * p.horizontal_sigma_mps());
  // At 1 s only the wander is correlated: exp(-1/10) of its share of the variance.
  const double expected = std::exp(-0.1) * (0.02 * 0.02) / (0.03 * 0.03 + 0.02 * 0.02);
  EXPECT_NEAR(s.lag_corr_east, expected, 0.03);
}

TEST(VelocityNoise, TheWanderDecorrelatesOverItsTimeWhateverTheEpochRate) {
  VelocityNoiseParams p;
  p.white_sigma_mps = 0.0;
  p.wander_sigma_mps = 0.05;
  p.wander_tau_s = 5.0;
  const AxisStats at_1hz = stats_of(p, 3, milliseconds{1000}, 100000, 5);   // a lag of 5 s
  const AxisStats at_10hz = stats_of(p, 3, milliseconds{100}, 400000, 50);  // the same 5 s
  EXPECT_NEAR(at_1hz.sd_east, 0.05, 0.004);
  EXPECT_NEAR(at_10hz.sd_east, 0.05, 0.006);
  EXPECT_NEAR(at_1hz.lag_corr_east, std::exp(-1.0), 0.04);
  EXPECT_NEAR(at_10hz.lag_corr_east, std::exp(-1.0), 0.06);
}

TEST(VelocityNoise, TheSameSeedGivesTheSameErrorsAndAResetStartsThemAgain) {
  const VelocityNoiseParams p;
  VelocityNoise a(p, 42), b(p, 42), c(p, 43);
  std::vector<Enu> first;
  for (int k = 0; k < 20; ++k) {
    const Enu ea = a.error_at(milliseconds{100} * k);
    const Enu eb = b.error_at(milliseconds{100} * k);
    EXPECT_EQ(ea.east_m, eb.east_m);
    EXPECT_EQ(ea.up_m, eb.up_m);
    EXPECT_NE(ea.north_m, c.error_at(milliseconds{100} * k).north_m);
    first.push_back(ea);
  }
  a.reset();
  for (int k = 0; k < 20; ++k) EXPECT_EQ(a.error_at(milliseconds{100} * k).north_m, first[k].north_m);
}

TEST(VelocityNoise, BothSigmasZeroIsOffAndTheRangesAreChecked) {
  VelocityNoiseParams p;
  EXPECT_FALSE(p.off());
  p.white_sigma_mps = p.wander_sigma_mps = 0.0;
  EXPECT_TRUE(p.off());
  VelocityNoise v(p, 1);
  EXPECT_EQ(v.error_at(milliseconds{0}).east_m, 0.0);
  EXPECT_NO_THROW(validate(VelocityNoiseParams{}));
  VelocityNoiseParams bad;
  bad.wander_tau_s = 0.0;
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad = {};
  bad.white_sigma_mps = -0.1;
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad = {};
  bad.static_clamp_mps = 2.0;
  EXPECT_THROW(validate(bad), std::invalid_argument);
}

}  // namespace
}  // namespace gpsemu::noise
