// The cgrw statistics and fit: measuring a series, fit -> simulate -> measure round trips on
// real receivers' statistics, scale invariance, and rejection of invalid parameters.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "emulator/model/noise/cgrw_fit.hpp"
#include "emulator/model/noise/cgrw_model.hpp"
#include "tests/support/noise_configs.hpp"

namespace gpsemu::noise {
namespace {
namespace cgrw_fit_test {

TEST(NoiseCgrwStatistics, MeasuresTheFourWidths) {
  const std::vector<double> parabola{0, 1, 3, 6, 10};  // d1 1 2 3 4, d2 1 1 1
  const CgrwAxis a = measure_cgrw_axis(parabola);
  EXPECT_DOUBLE_EQ(a.width_m, 10.0);
  EXPECT_DOUBLE_EQ(a.width_d1_m, 3.0);
  EXPECT_DOUBLE_EQ(a.width_d2_m, 0.0);
  EXPECT_DOUBLE_EQ(a.sigma_d2_m, 0.0);
  const std::vector<double> zigzag{0, 1, 0, 1, 0};  // d1 1 -1 1 -1, d2 -2 2 -2
  const CgrwAxis z = measure_cgrw_axis(zigzag);
  EXPECT_DOUBLE_EQ(z.width_m, 1.0);
  EXPECT_DOUBLE_EQ(z.width_d1_m, 2.0);
  EXPECT_DOUBLE_EQ(z.width_d2_m, 4.0);
  EXPECT_NEAR(z.sigma_d2_m, std::sqrt(96.0 / 27.0), 1e-12);  // population std
  EXPECT_THROW((void)measure_cgrw_axis(std::vector<double>{1, 2}), std::invalid_argument);
}

TEST(NoiseCgrwStatistics, MeanOverWholeWindows) {
  std::vector<double> x{0, 1, 3, 6, 10, 0, 1, 0, 1, 0, 99};  // two windows of 5 and a stray
  const CgrwAxis m = mean_cgrw_statistics(x, 5);
  EXPECT_DOUBLE_EQ(m.width_m, 5.5);
  EXPECT_DOUBLE_EQ(m.width_d1_m, 2.5);
  EXPECT_DOUBLE_EQ(m.width_d2_m, 2.0);
}

// Simulates the fitted walk through the public model with another seed than the fit's, 4 hours
// at rate_hz, and returns the mean statistics over the fit's windows for the east axis.
CgrwAxis round_trip(const CgrwAxis& target) {
  NoiseConfig c;
  c.model = Model::cgrw;
  c.cgrw.east = c.cgrw.north = c.cgrw.up = target;
  auto model = make_noise_model(c, 99);
  std::vector<double> east;
  for (int i = 0; i < 4 * 3600; ++i) east.push_back(model->offset_at(std::chrono::seconds(i)).east_m);
  return mean_cgrw_statistics(east, 300);
}

void expect_within(const CgrwAxis& got, const CgrwAxis& want, double tol, const char* what) {
  EXPECT_NEAR(got.width_m / want.width_m, 1.0, tol) << what << " width_m";
  EXPECT_NEAR(got.width_d1_m / want.width_d1_m, 1.0, tol) << what << " width_d1_m";
  EXPECT_NEAR(got.width_d2_m / want.width_d2_m, 1.0, tol) << what << " width_d2_m";
  EXPECT_NEAR(got.sigma_d2_m / want.sigma_d2_m, 1.0, tol) << what << " sigma_d2_m";
}

// Statistics of data/real's receivers at 1 Hz (data/real/README.md; numbers copied so the test
// does not need that folder).
TEST(NoiseCgrwFit, RoundTripRecoversSmoothReceivers) {
  expect_within(round_trip({4.84, 0.63, 0.68, 0.083}), {4.84, 0.63, 0.68, 0.083}, 0.3,
                "u-blox east");
  expect_within(round_trip({2.24, 0.15, 0.17, 0.024}), {2.24, 0.15, 0.17, 0.024}, 0.3,
                "u-blox north");
  expect_within(round_trip(cgrw_preset(3.0).east), cgrw_preset(3.0).east, 0.1, "preset");
}

// Receivers with jumps: width_d2 / sigma_d2 of 14-17, where Gaussian innovations give at most
// about 6.5 (cgrw_fit.hpp). Only a compromise exists; the width (the knob) and the
// first-difference width are kept, the other two are off by less than a factor 2, and the fit
// says so. If the model learns heavy tails, tighten this to 30% on all four.
TEST(NoiseCgrwFit, RoundTripOnReceiversWithJumpsIsACompromise) {
  for (const CgrwAxis& t : {CgrwAxis{1.16, 0.60, 1.19, 0.075}, CgrwAxis{4.68, 1.05, 1.64, 0.118}}) {
    const CgrwAxis got = round_trip(t);
    EXPECT_NEAR(got.width_m / t.width_m, 1.0, 0.3);
    EXPECT_NEAR(got.width_d1_m / t.width_d1_m, 1.0, 0.3);
    EXPECT_GT(got.width_d2_m / t.width_d2_m, 0.5);
    EXPECT_LT(got.sigma_d2_m / t.sigma_d2_m, 2.0);
    EXPECT_GT(fit_cgrw_axis(t, 300).worst_ratio, 1.3);
  }
}

TEST(NoiseCgrwFit, ScaleInvariant) {
  const CgrwFit a = fit_cgrw_axis(cgrw_preset(0.1).east, 300);
  const CgrwFit b = fit_cgrw_axis(cgrw_preset(10.0).east, 300);
  EXPECT_NEAR(b.internal.p_max_m / a.internal.p_max_m, 100.0, 1e-9);
  EXPECT_NEAR(b.internal.v_max_m / a.internal.v_max_m, 100.0, 1e-9);
  EXPECT_NEAR(b.internal.a_max_m / a.internal.a_max_m, 100.0, 1e-9);
  EXPECT_NEAR(b.internal.sigma_m / a.internal.sigma_m, 100.0, 1e-9);
  EXPECT_LT(a.worst_ratio, 1.05);
}

void expect_throw_naming(const CgrwParams& p, const std::string& name) {
  test::expect_throw_naming(test::cgrw(p), name);
}

TEST(NoiseCgrwFit, InvalidParametersThrowNamingThem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const CgrwParams ok = cgrw_preset(1.0);
  CgrwParams p = ok;
  p.east.width_m = 0.0;
  expect_throw_naming(p, "cgrw.east.width_m");
  p = ok;
  p.north.sigma_d2_m = nan;
  expect_throw_naming(p, "cgrw.north.sigma_d2_m");
  p = ok;
  p.up.width_d1_m = -0.1;
  expect_throw_naming(p, "cgrw.up.width_d1_m");
  p = ok;
  p.east.width_d2_m = inf;
  expect_throw_naming(p, "cgrw.east.width_d2_m");
  p = ok;
  p.rate_hz = -1.0;
  expect_throw_naming(p, "cgrw.rate_hz");
  p = ok;
  p.window_s = 0.0;
  expect_throw_naming(p, "cgrw.window_s");
  p = ok;
  p.window_s = 5.0;  // 5 samples: too short to fit
  expect_throw_naming(p, "cgrw.window_s");
  // Impossible for any series.
  p = ok;
  p.north.sigma_d2_m = 0.6 * p.north.width_d2_m;
  expect_throw_naming(p, "cgrw.north.sigma_d2_m");
  p = ok;
  p.east.width_d1_m = 2.5 * p.east.width_m;
  expect_throw_naming(p, "cgrw.east.width_d1_m");
  p = ok;
  p.up.width_d2_m = 2.5 * p.up.width_d1_m;
  expect_throw_naming(p, "cgrw.up.width_d2_m");
  // Possible for a series, not for this walk: velocity range near twice the position range
  // with a gentle acceleration.
  p = ok;
  p.east = {1.0, 1.9, 0.2, 0.09};
  expect_throw_naming(p, "cgrw.east: the cgrw walk cannot reproduce");
  EXPECT_NO_THROW((void)fit_cgrw_axis(p.east, 300, "x", std::numeric_limits<double>::infinity()));
  EXPECT_THROW((void)cgrw_preset(-1.0), std::invalid_argument);
  EXPECT_THROW((void)cgrw_preset(nan), std::invalid_argument);
}

}  // namespace cgrw_fit_test
}  // namespace
}  // namespace gpsemu::noise
