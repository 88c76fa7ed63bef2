// The memoryless noise models (gaussian, none), the factory and model names.
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
namespace gaussian_test {

using std::chrono::milliseconds;

using test::expect_throw_naming;
using test::gaussian;
using test::lag1_autocorrelation;
using test::mean_of;
using test::sd_of;

TEST(NoiseGaussian, UnitSigmaIsWhiteWithUnitStd) {
  auto model = make_noise_model(gaussian({0, 1}, {0, 1}, {0, 1}), 5);
  std::vector<double> e, n, u;
  for (int i = 0; i < 100'000; ++i) {
    const Enu x = model->offset_at(milliseconds(100 * i));  // 10 Hz epochs
    e.push_back(x.east_m);
    n.push_back(x.north_m);
    u.push_back(x.up_m);
  }
  for (const auto* axis : {&e, &n, &u}) {
    EXPECT_LT(std::abs(lag1_autocorrelation(*axis)), 0.02);  // brief: < 0.1; s.e. 0.003
    EXPECT_NEAR(sd_of(*axis), 1.0, 0.02);                     // brief: 5%; s.e. 0.2%
    EXPECT_NEAR(mean_of(*axis), 0.0, 0.02);
  }
  // Axes are independent streams.
  double cross = 0.0;
  for (std::size_t i = 0; i < e.size(); ++i) cross += e[i] * n[i];
  EXPECT_LT(std::abs(cross / static_cast<double>(e.size())), 0.02);
}

TEST(NoiseGaussian, MeanAndSigmaPerAxis) {
  auto model = make_noise_model(gaussian({2.0, 0.5}, {-1.0, 3.0}, {0.25, 0.0}), 9);
  std::vector<double> e, n;
  for (int i = 0; i < 50'000; ++i) {
    const Enu x = model->offset_at(milliseconds(1000 * i));
    e.push_back(x.east_m);
    n.push_back(x.north_m);
    EXPECT_EQ(x.up_m, 0.25);  // sigma 0: exactly the mean
  }
  EXPECT_NEAR(mean_of(e), 2.0, 0.01);
  EXPECT_NEAR(sd_of(e), 0.5, 0.01);
  EXPECT_NEAR(mean_of(n), -1.0, 0.06);
  EXPECT_NEAR(sd_of(n), 3.0, 0.06);
}

TEST(NoiseGaussian, OneFreshDrawPerQuery) {
  auto model = make_noise_model(gaussian({0, 1}, {0, 1}, {0, 1}), 1);
  const Enu a = model->offset_at(milliseconds(0));
  const Enu b = model->offset_at(milliseconds(0));
  EXPECT_NE(a.east_m, b.east_m);
}

TEST(NoiseGaussian, SameSeedSameSequenceOtherSeedDiffers) {
  const NoiseConfig c = gaussian({0, 1}, {0, 1}, {0, 1});
  auto a = make_noise_model(c, 77), b = make_noise_model(c, 77), d = make_noise_model(c, 78);
  int same = 0;
  for (int i = 0; i < 1000; ++i) {
    const Enu x = a->offset_at(milliseconds(i)), y = b->offset_at(milliseconds(i));
    EXPECT_EQ(x.east_m, y.east_m);
    EXPECT_EQ(x.north_m, y.north_m);
    EXPECT_EQ(x.up_m, y.up_m);
    same += x.east_m == d->offset_at(milliseconds(i)).east_m;
  }
  EXPECT_EQ(same, 0);
}

TEST(NoiseGaussian, InvalidParametersThrowNamingThem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  expect_throw_naming(gaussian({0, 1}, {0, -1}, {0, 1}), "gaussian.north.sigma_m");
  expect_throw_naming(gaussian({0, 1}, {0, 1}, {nan, 1}), "gaussian.up.mean_m");
  expect_throw_naming(gaussian({0, inf}, {0, 1}, {0, 1}), "gaussian.east.sigma_m");
}

TEST(NoiseNone, IsZero) {
  NoiseConfig c;
  c.model = Model::none;
  auto model = make_noise_model(c, 3);
  for (int i = 0; i < 10; ++i) {
    const Enu x = model->offset_at(milliseconds(100 * i));
    EXPECT_EQ(x.east_m, 0.0);
    EXPECT_EQ(x.north_m, 0.0);
    EXPECT_EQ(x.up_m, 0.0);
  }
}

TEST(NoiseModelNames, ParseAndPrintRoundTrip) {
  for (Model m : {Model::none, Model::cgrw, Model::chrono, Model::gaussian, Model::gauss_markov}) EXPECT_EQ(parse_model(to_string(m)), m);
  EXPECT_THROW((void)parse_model("brownian"), std::invalid_argument);
}

TEST(NoiseFactory, DefaultConfigBuildsACgrwModel) {
  auto model = make_noise_model(NoiseConfig{}, 1);
  const Enu x = model->offset_at(milliseconds(0));
  EXPECT_TRUE(std::isfinite(x.east_m) && std::isfinite(x.north_m) && std::isfinite(x.up_m));
}

}  // namespace gaussian_test
}  // namespace
}  // namespace gpsemu::noise
