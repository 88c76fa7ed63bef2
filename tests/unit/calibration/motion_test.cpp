// A log that moves is refused by calibration, naming its distance and speed (issue 16: a
// `sim:circle` run was calibrated as noise as wide as the circle), unless --detrend removes a
// smooth trajectory first; the real stationary logs still pass.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "emulator/calibration/calibrate.hpp"
#include "emulator/calibration/motion.hpp"
#include "tests/support/calibration_logs.hpp"

namespace gpsemu::calibration {
namespace {

// sim:circle's defaults: radius 20 m at 2 m/s.
Enu circle(double t_s) { return {20.0 * std::sin(t_s / 10.0), 20.0 * (1.0 - std::cos(t_s / 10.0)), 0.0}; }

noise::NoiseConfig smooth_noise() {
  noise::NoiseConfig c;
  c.model = noise::Model::gauss_markov;
  c.gauss_markov_order = 2;
  c.gauss_markov = {{{0.3, 10}, {0.3, 10}, {0.5, 10}}};
  return c;
}

TEST(Motion, CircleIsRefusedNamingDistanceAndSpeed) {
  const std::string log = test::model_log(smooth_noise(), 1, 1.0, 300.0, 5, false, circle);
  try {
    (void)calibrate(read_receiver_log(log), CalibrateOptions{1, 1});
    FAIL() << "a circle was calibrated as noise";
  } catch (const MotionError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("net displacement"), std::string::npos) << what;
    EXPECT_NE(what.find("sustained speed 1."), std::string::npos) << what;  // a 40 m chord over 30 s
    EXPECT_NE(what.find("--detrend"), std::string::npos) << what;
    EXPECT_NE(what.find("limits for this log's noise"), std::string::npos) << what;
  }
}

TEST(Motion, DetrendRemovesTheCircleAndSaysHowMuch) {
  const std::string log = test::model_log(smooth_noise(), 1, 1.0, 300.0, 5, false, circle);
  CalibrateOptions o{1, 1};
  o.detrend = true;
  const Calibration c = calibrate(read_receiver_log(log), o);
  EXPECT_TRUE(c.motion.moving);
  ASSERT_FALSE(c.notes.empty());
  EXPECT_NE(c.notes.front().find("detrended"), std::string::npos) << c.notes.front();
  // What is left is metres at most, not the circle's 40 m.
  EXPECT_LT(c.real[0].range_m, 5.0);
  EXPECT_LT(c.real[1].range_m, 5.0);
  EXPECT_NE(config_toml(c, "circle.log").find("# detrended"), std::string::npos);
}

TEST(Motion, StationaryNoiseIsNotMotion) {
  const std::string log = test::model_log(smooth_noise(), 2, 5.0, 600.0, 5);
  ReceiverLog r = read_receiver_log(log);
  const MotionCheck m = check_motion(to_enu_series(r));
  EXPECT_FALSE(m.moving) << m.describe();
}

TEST(Motion, RealStationaryLogsPass) {
  const std::string dir = GPSEMU_SOURCE_DIR "/../shared/data/real";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " not found: this test did not run";
  int seen = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".log") continue;
    ReceiverLog r = read_receiver_log_file(entry.path().string());
    const MotionCheck m = check_motion(to_enu_series(r));
    EXPECT_FALSE(m.moving) << entry.path() << ": " << m.describe() << "; " << m.describe_limits();
    ++seen;
  }
  EXPECT_GE(seen, 3);
}

// A slow drift: 1 cm/s east, 6 m over the 10 minutes (5.4 m between the first and last tenth).
Enu drift(double t_s) { return {0.01 * t_s, 0.0, 0.0}; }

noise::NoiseConfig gm2(double sigma_m, double tau_s) {
  noise::NoiseConfig c;
  c.model = noise::Model::gauss_markov;
  c.gauss_markov_order = 2;
  c.gauss_markov = {{{sigma_m, tau_s}, {sigma_m, tau_s}, {2 * sigma_m, tau_s}}};
  return c;
}

// On a receiver quiet to 5 cm the drift is motion (the old fixed 20 m limit let it through).
TEST(Motion, SlowDriftOnAQuietReceiverIsRefused) {
  const std::string log = test::model_log(gm2(0.05, 30), 5, 1.0, 600.0, 6, false, drift);
  ReceiverLog r = read_receiver_log(log);
  const MotionCheck m = check_motion(to_enu_series(r));
  EXPECT_TRUE(m.moving) << m.describe() << "; " << m.describe_limits();
  EXPECT_LT(m.displacement_m, 20.0);
  EXPECT_GT(m.displacement_m, 5.0);
  try {
    (void)calibrate(read_receiver_log(log), CalibrateOptions{1, 1});
    FAIL() << "a 1 cm/s drift on a 5 cm receiver was calibrated as noise";
  } catch (const MotionError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("net displacement 5."), std::string::npos) << what;
    EXPECT_NE(what.find(fmt::format("{:.1f} m and {:.2f} m/s", m.displacement_limit_m, m.speed_limit_mps)),
              std::string::npos) << what;
  }
}

// On a noisy receiver, 7-10 m wide (wander sigma 3 m with tau 100 s, 0.3 m of white jitter),
// the same drift is within what the wander itself does between the first and last minute (about
// 4 m rms per axis): not refused.
TEST(Motion, TheSameDriftOnANoisyReceiverIsExplainedByTheNoise) {
  noise::NoiseConfig noisy;
  noisy.model = noise::Model::composite;
  noisy.composite.smooth_gm = {{{3.0, 100}, {3.0, 100}, {6.0, 100}}};
  noisy.composite.axes = {{{0.3, 0, 0, 0}, {0.3, 0, 0, 0}, {0.6, 0, 0, 0}}};
  const std::string log = test::model_log(noisy, 5, 1.0, 600.0, 6, false, drift);
  ReceiverLog r = read_receiver_log(log);
  const EnuSeries s = to_enu_series(r);
  const MotionCheck m = check_motion(s);
  EXPECT_FALSE(m.moving) << m.describe() << "; " << m.describe_limits();
  EXPECT_GT(m.displacement_m, kMinDisplacementLimit_m);  // beyond the floor: the noise's scale decides
  const AxisStats north = measure_axis(s.axis_m[1], s.rate_hz, s.size());
  EXPECT_GT(north.range_m, 6.0) << "the noise alone, without the drift";
}

}  // namespace
}  // namespace gpsemu::calibration
