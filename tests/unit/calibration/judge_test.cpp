// The judge's constant-velocity Kalman filter: fed data from its own model (white acceleration of
// its process noise, white measurement noise of its sigma) it is consistent: NIS mean ~ 2 (its
// dimension), 95th percentile ~ 5.99 (chi-square, 2 degrees of freedom), innovations white. Fed
// smooth correlated noise it is not (innovations correlated), which is what it judges models by.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <nlohmann/json.hpp>

#include "emulator/calibration/judge.hpp"
#include "emulator/model/noise/rng.hpp"
#include "tests/support/calibration_logs.hpp"

namespace gpsemu::calibration {
namespace {
namespace judge_test {

// A constant-velocity target (white acceleration, spectral density q) measured with sigma.
std::vector<double> cv_track(std::uint64_t stream, std::size_t n, double dt, double q, double sigma) {
  noise::Rng rng(42, stream);
  std::vector<double> z;
  double p = 0.0, v = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    // Exact discretisation: (dp, dv) ~ N(0, q [[dt^3/3, dt^2/2], [dt^2/2, dt]]).
    const double l00 = std::sqrt(q * dt * dt * dt / 3.0);
    const double l10 = q * dt * dt / 2.0 / l00;
    const double l11 = std::sqrt(q * dt - l10 * l10);
    const double a = rng.normal(), b = rng.normal();
    p += v * dt + l00 * a;
    v += l10 * a + l11 * b;
    z.push_back(p + sigma * rng.normal());
  }
  return z;
}

TEST(Judge, FilterOnItsOwnModelIsConsistent) {
  const double q = kJudgeProcessNoise_m2ps3, sigma = 0.3;
  const auto e = cv_track(0, 20000, 1.0, q, sigma), n = cv_track(1, 20000, 1.0, q, sigma);
  const FilterScore s = run_cv_filter(e, n, 1.0, sigma, q);
  EXPECT_NEAR(s.nis_mean, 2.0, 0.1);
  EXPECT_NEAR(s.nis_p95, 5.99, 0.4);
  EXPECT_NEAR(s.innov_rho1, 0.0, 0.03);
}

TEST(Judge, GapsArePredictedAcross) {
  const double q = kJudgeProcessNoise_m2ps3, sigma = 0.3;
  auto e = cv_track(2, 5000, 0.2, q, sigma), n = cv_track(3, 5000, 0.2, q, sigma);
  for (std::size_t k = 100; k < e.size(); k += 37) e[k] = n[k] = std::nan("");
  const FilterScore s = run_cv_filter(e, n, 5.0, sigma, q);
  EXPECT_NEAR(s.nis_mean, 2.0, 0.15);
}

TEST(Judge, SmoothNoiseGivesCorrelatedInnovations) {
  noise::NoiseConfig gm;
  gm.model = noise::Model::gauss_markov;
  gm.gauss_markov_order = 2;
  gm.gauss_markov = {{{1.0, 30}, {1.0, 30}, {1.0, 30}}};
  const std::string log = test::model_log(gm, 1, 1.0, 600.0, 6);
  ReceiverLog r = read_receiver_log(log);
  const EnuSeries s = to_enu_series(r);
  const FilterScore f = run_cv_filter(s.axis_m[0], s.axis_m[1], s.rate_hz, 0.3);
  EXPECT_GT(f.innov_rho1, 0.5);
}

TEST(Judge, JudgesEveryCalibratedModelAndWritesTheJson) {
  noise::NoiseConfig gm;
  gm.model = noise::Model::gauss_markov;
  gm.gauss_markov_order = 2;
  gm.gauss_markov = {{{0.5, 20}, {0.4, 20}, {1.0, 20}}};
  const ReceiverLog log = read_receiver_log(test::model_log(gm, 5, 1.0, 400.0, 5));
  const Calibration c = calibrate(log, CalibrateOptions{1, 2});
  const Judgement j = judge(c, stated_sigma_m(log, c), 2, 1);
  EXPECT_NEAR(j.sigma_m, 0.9 * kUereM / std::sqrt(2.0), 1e-9);  // the log states HDOP 0.9
  EXPECT_EQ(j.models.size(), c.models.size());
  const auto json = nlohmann::json::parse(judgement_json(j));
  for (const char* key : {"nis_mean", "nis_p95", "innov_rho1"}) {
    EXPECT_TRUE(json["real"].contains(key)) << key;
    EXPECT_TRUE(json["models"]["composite"].contains(key)) << key;
  }
  EXPECT_EQ(json["best"], j.best);
  EXPECT_TRUE(j.models.count(j.best));
  // A model of white noise is the farthest from a smooth receiver.
  EXPECT_NE(j.best, "gaussian");
}

}  // namespace judge_test
}  // namespace
}  // namespace gpsemu::calibration
