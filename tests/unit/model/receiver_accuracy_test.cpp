// The receiver's reported accuracy (GST sigmas, hence hAcc/vAcc/eph) against the error it actually
// applies: for every noise model the reported 1-sigma matches the scatter of the positions over a long
// run; the quality the noise was measured at and the receiver's own reported/actual ratio.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "emulator/model/noise/cgrw_model.hpp"
#include "emulator/model/receiver.hpp"

namespace gpsemu {
namespace {
namespace receiver_accuracy_test {

using namespace std::chrono;

const UtcNs kStart = parse_iso8601_utc("2024-05-01T12:00:00Z");
const LocalFrame kFrame({43.0725, -89.4125, 260.0});
const sources::Truth kAtOrigin{};

UtcNs at(double seconds) { return kStart + nanoseconds{std::llround(seconds * 1e9)}; }

/// RMS of the emulated error, the mean reported sigma, and the RMS of the error in units of the
/// sigma reported with it (1 for an honest receiver, whatever the sigma does from epoch to epoch),
/// per axis, over `seconds` at 1 Hz.
struct Comparison {
  Enu scatter_m, reported_m, normalised;
};
Comparison compare(const noise::NoiseConfig& config, ReceiverOptions o, int seconds) {
  // The sigma is estimated with one seed and the run uses another: the claim is about the model.
  o.noise_sigma_m = estimate_noise_sigma_m(config, 11);
  Receiver rx(kFrame, o, noise::make_noise_model(config, 12), kStart);
  Enu sum_sq{}, sum_sigma{}, sum_z{};
  int n = 0;
  for (int k = 0; k < seconds; ++k) {
    const nmea::Fix fix = rx.fix_at(at(k), kAtOrigin);
    if (!fix.has_fix()) continue;
    const Enu e = kFrame.to_enu({fix.lat_deg, fix.lon_deg, fix.alt_msl_m});
    sum_sq = {sum_sq.east_m + e.east_m * e.east_m, sum_sq.north_m + e.north_m * e.north_m, sum_sq.up_m + e.up_m * e.up_m};
    sum_sigma = {sum_sigma.east_m + fix.sigma_lon_m, sum_sigma.north_m + fix.sigma_lat_m, sum_sigma.up_m + fix.sigma_alt_m};
    const auto z2 = [](double e, double sigma) { return (e / sigma) * (e / sigma); };
    sum_z = {sum_z.east_m + z2(e.east_m, fix.sigma_lon_m), sum_z.north_m + z2(e.north_m, fix.sigma_lat_m),
             sum_z.up_m + z2(e.up_m, fix.sigma_alt_m)};
    ++n;
  }
  EXPECT_GT(n, seconds - 5);
  return {{std::sqrt(sum_sq.east_m / n), std::sqrt(sum_sq.north_m / n), std::sqrt(sum_sq.up_m / n)},
          {sum_sigma.east_m / n, sum_sigma.north_m / n, sum_sigma.up_m / n},
          {std::sqrt(sum_z.east_m / n), std::sqrt(sum_z.north_m / n), std::sqrt(sum_z.up_m / n)}};
}

/// The reported sigma is `ratio` x the error's: the error in units of the reported sigma has an
/// RMS of 1 / ratio, within `tolerance` (relative).
void expect_within(const Comparison& c, double ratio, double tolerance, const std::string& what) {
  const auto check = [&](double scatter, double reported, double normalised, const char* axis) {
    EXPECT_GT(scatter, 0.0) << what << " " << axis;
    EXPECT_NEAR(1.0 / normalised, ratio, tolerance * ratio)
        << what << " " << axis << ": the error is " << normalised << " reported sigmas RMS (reported " << reported
        << " m on average, scatter " << scatter << " m)";
  };
  check(c.scatter_m.east_m, c.reported_m.east_m, c.normalised.east_m, "east");
  check(c.scatter_m.north_m, c.reported_m.north_m, c.normalised.north_m, "north");
  check(c.scatter_m.up_m, c.reported_m.up_m, c.normalised.up_m, "up");
}

noise::NoiseConfig of(noise::Model model) {
  noise::NoiseConfig c;
  c.model = model;
  return c;
}

TEST(ReceiverAccuracy, ReportedSigmaMatchesTheScatterOfEveryNoiseModelWithin30Percent) {
  constexpr int kSeconds = 3 * 3600;
  noise::NoiseConfig gaussian = of(noise::Model::gaussian);
  gaussian.gaussian = {noise::GaussianAxis{0.0, 1.5}, noise::GaussianAxis{0.0, 1.0}, noise::GaussianAxis{0.0, 2.0}};
  noise::NoiseConfig cgrw = of(noise::Model::cgrw);
  cgrw.cgrw = noise::cgrw_preset(2.0);
  noise::NoiseConfig gm1 = of(noise::Model::gauss_markov);
  gm1.gauss_markov = {noise::GaussMarkovAxis{0.8, 30.0}, noise::GaussMarkovAxis{1.2, 30.0}, noise::GaussMarkovAxis{2.0, 60.0}};
  noise::NoiseConfig gm2 = gm1;
  gm2.gauss_markov_order = 2;
  noise::NoiseConfig composite = of(noise::Model::composite);
  composite.composite.axes = {noise::CompositeAxis{0.05, 0.01, 0.5, 20.0, 0.3, 120.0},
                              noise::CompositeAxis{0.05, 0.01, 0.5, 20.0, 0.3, 120.0},
                              noise::CompositeAxis{0.1, 0.01, 0.8, 20.0, 0.5, 120.0}};
  const noise::NoiseConfig chrono = of(noise::Model::chrono);
  for (const auto& [name, config] : {std::pair{"gaussian", gaussian}, std::pair{"cgrw", cgrw}, std::pair{"gauss-markov", gm1},
                                     std::pair{"gauss-markov order 2", gm2}, std::pair{"composite", composite},
                                     std::pair{"chrono", chrono}}) {
    expect_within(compare(config, ReceiverOptions{}, kSeconds), 1.0, 0.3, name);
  }
}

TEST(ReceiverAccuracy, TheScalesOfQualityAndGeometryApplyToTheReportedSigmaToo) {
  noise::NoiseConfig c = of(noise::Model::gaussian);
  c.gaussian = {noise::GaussianAxis{0.0, 1.0}, noise::GaussianAxis{0.0, 1.0}, noise::GaussianAxis{0.0, 1.5}};
  ReceiverOptions o;
  o.quality = nmea::FixQuality::dgps;
  expect_within(compare(c, o, 2000), 1.0, 0.15, "dgps");
  o.quality = nmea::FixQuality::gps;
  o.noise_scales_with_dop = true;
  o.sky_mask = parse_sky_mask("urban-canyon");
  expect_within(compare(c, o, 2000), 1.0, 0.15, "noise scaled with DOP in an urban canyon");
}

TEST(ReceiverAccuracy, TheAccuracyRatioMakesTheReceiverOptimistic) {
  noise::NoiseConfig c = of(noise::Model::gaussian);
  ReceiverOptions o;
  o.accuracy_ratio = 0.4;
  expect_within(compare(c, o, 2000), 0.4, 0.15, "ratio 0.4");
}

TEST(ReceiverAccuracy, NoiseMeasuredAtRtkFixedIsTheReceiversOwnThereAndGrowsWhenTheFixFallsBack) {
  noise::NoiseConfig c = of(noise::Model::gaussian);
  c.gaussian = {noise::GaussianAxis{0.0, 0.01}, noise::GaussianAxis{0.0, 0.01}, noise::GaussianAxis{0.0, 0.02}};
  ReceiverOptions o;
  o.noise_quality = nmea::FixQuality::rtk_fixed;
  o.quality = nmea::FixQuality::rtk_fixed;
  const Comparison fixed = compare(c, o, 2000);
  EXPECT_NEAR(fixed.scatter_m.east_m, 0.01, 0.001);
  EXPECT_NEAR(fixed.scatter_m.up_m, 0.02, 0.002);
  o.quality = nmea::FixQuality::rtk_float;  // 10x an RTK-fixed error
  const Comparison fallen = compare(c, o, 2000);
  EXPECT_NEAR(fallen.scatter_m.east_m, 0.1, 0.01);
  expect_within(fallen, 1.0, 0.15, "rtk-float");
  EXPECT_DOUBLE_EQ(noise_scale(nmea::FixQuality::gps, nmea::FixQuality::rtk_fixed), 100.0);
  EXPECT_DOUBLE_EQ(noise_scale(nmea::FixQuality::dgps, nmea::FixQuality::gps), 0.4);
}

}  // namespace receiver_accuracy_test
}  // namespace
}  // namespace gpsemu
