// fit_velocity: the velocity error's sigma, white/wander split and static clamp recovered from the
// speeds at rest of a known model (simulated as the emulator reports them), and what too few
// reports or a chipset reporting only zeros give.
#include "emulator/calibration/velocity_fit.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "emulator/model/noise/velocity_noise.hpp"

namespace gpsemu::calibration {
namespace {
namespace velocity_fit_test {

/// The speeds a receiver with `params` reports at rest, one a second.
std::vector<SpeedReport> speeds_of(const noise::VelocityNoiseParams& params, std::size_t n) {
  noise::VelocityNoise noise(params, 11);
  std::vector<SpeedReport> out;
  for (std::size_t k = 0; k < n; ++k) {
    const Enu e = noise.error_at(std::chrono::seconds(static_cast<std::int64_t>(k)));
    const double s = std::hypot(e.east_m, e.north_m);
    out.push_back({static_cast<double>(k), static_cast<float>(s < params.static_clamp_mps ? 0.0 : s)});
  }
  return out;
}

TEST(VelocityFit, RecoversTheSigmaAndTheWhiteWanderSplitOfAKnownModel) {
  noise::VelocityNoiseParams truth;
  truth.white_sigma_mps = 0.04;
  truth.wander_sigma_mps = 0.0;
  const VelocityFit white = fit_velocity(speeds_of(truth, 20000), 1.0, 3);
  ASSERT_TRUE(white.fitted);
  EXPECT_NEAR(white.params.horizontal_sigma_mps(), 0.04, 0.002);
  EXPECT_LT(white.params.wander_sigma_mps, 0.015) << "white noise has no lag-1 correlation";
  EXPECT_EQ(white.params.static_clamp_mps, 0.0);
  EXPECT_NEAR(white.model_median_mps, white.median_mps, 0.1 * white.median_mps);
  EXPECT_NEAR(white.model_p95_mps, white.p95_mps, 0.1 * white.p95_mps);

  truth.white_sigma_mps = 0.01;
  truth.wander_sigma_mps = 0.05;
  const VelocityFit wander = fit_velocity(speeds_of(truth, 20000), 1.0, 3);
  EXPECT_NEAR(wander.params.horizontal_sigma_mps(), std::hypot(0.01, 0.05), 0.006);
  EXPECT_GT(wander.params.wander_sigma_mps, 3.0 * wander.params.white_sigma_mps);
}

TEST(VelocityFit, AClampingChipsetsZerosGiveItsClampAndTheTailItsSigma) {
  noise::VelocityNoiseParams truth;
  truth.white_sigma_mps = 0.05;
  truth.wander_sigma_mps = 0.0;
  truth.static_clamp_mps = 0.08;  // about 72% of the speeds reported as 0
  const VelocityFit fit = fit_velocity(speeds_of(truth, 20000), 1.0, 3);
  EXPECT_GT(fit.zero_share, 0.6);
  EXPECT_NEAR(fit.params.static_clamp_mps, 0.08, 0.008);
  EXPECT_NEAR(fit.params.horizontal_sigma_mps(), 0.05, 0.005);
}

TEST(VelocityFit, OnlyZerosGiveTheDefaultClampAndTooFewReportsNothing) {
  std::vector<SpeedReport> zeros;
  for (int k = 0; k < 100; ++k) zeros.push_back({static_cast<double>(k), 0.0f});
  const VelocityFit all_zero = fit_velocity(zeros, 1.0, 3);
  EXPECT_TRUE(all_zero.fitted);
  EXPECT_EQ(all_zero.params.static_clamp_mps, kAllZeroClamp_mps);
  EXPECT_EQ(all_zero.model_median_mps, 0.0);
  EXPECT_NE(velocity_toml(all_zero).find("velocity-static-clamp = 0.300"), std::string::npos) << velocity_toml(all_zero);

  zeros.resize(kMinSpeedReports - 1);
  const VelocityFit few = fit_velocity(zeros, 1.0, 3);
  EXPECT_FALSE(few.fitted);
  EXPECT_EQ(velocity_toml(few).find("velocity-noise"), std::string::npos);
}

}  // namespace velocity_fit_test
}  // namespace
}  // namespace gpsemu::calibration
