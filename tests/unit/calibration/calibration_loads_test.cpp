// Property: whatever `gpsemu calibrate` writes loads and runs with every noise model. Logs are
// generated from every model at 1, 5 and 10 Hz, 4 to 7 decimals of minutes, 60 s to 1 h (a
// seeded sample of that grid, so the test stays fast), plus the two cases of issue 16: a 5 Hz log
// quantised at 5 decimals whose second-difference width is exactly twice the first's, and a
// constant altitude (no noise on that axis, not 1e-9 m).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "emulator/calibration/calibrate.hpp"
#include "emulator/config/config.hpp"
#include "emulator/model/noise/cgrw_model.hpp"
#include "tests/support/calibration_logs.hpp"

namespace gpsemu::calibration {
namespace {
namespace calibration_loads_test {

const std::vector<std::string> kModels{"cgrw", "chrono", "gaussian", "gauss-markov", "composite", "none"};

noise::NoiseConfig generator(std::size_t i) {
  noise::NoiseConfig c;
  switch (i % 6) {
    case 0: c.model = noise::Model::cgrw, c.cgrw = noise::cgrw_preset(1.0); break;
    case 1: c.model = noise::Model::chrono; break;
    case 2: c.model = noise::Model::gaussian, c.gaussian = {{{0, 0.4}, {0, 0.3}, {0, 0.8}}}; break;
    case 3: c.model = noise::Model::gauss_markov, c.gauss_markov = {{{0.5, 30}, {0.3, 60}, {1.0, 40}}}; break;
    case 4:
      c.model = noise::Model::gauss_markov, c.gauss_markov_order = 2;
      c.gauss_markov = {{{0.5, 10}, {0.3, 20}, {1.0, 15}}};
      break;
    default:
      c.model = noise::Model::composite;
      c.composite.smooth_gm = {{{0.4, 20}, {0.3, 30}, {0.8, 20}}};
      c.composite.axes = {{{0.05, 0.01, 0.3, 20}, {0.05, 0.01, 0.3, 20}, {0.1, 0.0, 0.0, 0.0}}};
      break;
  }
  return c;
}

// Calibrates `log`, then loads the written config with each model and draws epochs from it.
void expect_every_model_runs(const std::string& log, const std::string& what) {
  const Calibration c = calibrate(read_receiver_log(log), CalibrateOptions{1, 2});
  const std::string toml = config_toml(c, "generated.log");
  for (const std::string& model : kModels) {
    SCOPED_TRACE(what + ", --noise " + model);
    Config config;
    try {
      config = build_config_from_text(toml, "calibrated.toml", {{"noise", {model}}});
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what() << "\n" << toml;
      continue;
    }
    std::unique_ptr<noise::NoiseModel> m;
    ASSERT_NO_THROW(m = noise::make_noise_model(config.receiver().noise, 7)) << toml;
    for (int k = 0; k < 50; ++k) {
      const Enu e = m->offset_at(std::chrono::milliseconds(200 * k));
      ASSERT_TRUE(std::isfinite(e.east_m) && std::isfinite(e.north_m) && std::isfinite(e.up_m)) << toml;
    }
  }
}

// One test a generator (each generator once: the composite's slow-part fits doubled a
// calibration's cost), so that each stays short and they run side by side.
class GeneratedLogs : public ::testing::TestWithParam<std::size_t> {};

TEST_P(GeneratedLogs, OfEveryModelRateResolutionAndLengthLoadAndRun) {
  std::mt19937_64 pick(16);  // the same seeded sample of the grid as when one test drew all six
  const double rates[] = {1.0, 5.0, 10.0};
  for (std::size_t i = 0; i < 6; ++i) {
    const double rate = rates[pick() % 3];
    const int decimals = 4 + static_cast<int>(pick() % 4);
    // 60 s to 1 h, log-uniform; at most 120 samples (a calibration's cost grows with the log's
    // length: the cgrw fit simulates walks as long as it, ~70 ms a sample under the sanitizers):
    // what loads does not depend on length.
    double seconds = 60.0 * std::pow(60.0, static_cast<double>(pick() % 1000) / 1000.0);
    seconds = std::min(seconds, 120.0 / rate);
    if (i != GetParam()) continue;
    const std::string what = fmt::format("generator {} at {} Hz, {} decimals, {:.0f} s", i % 6, rate, decimals, seconds);
    expect_every_model_runs(test::model_log(generator(i), 100 + i, rate, seconds, decimals), what);
  }
}

std::string generator_name(const ::testing::TestParamInfo<std::size_t>& info) {
  const char* names[] = {"cgrw", "chrono", "gaussian", "gauss_markov", "gauss_markov_2", "composite"};
  return names[info.param];
}

INSTANTIATE_TEST_SUITE_P(CalibrationLoads, GeneratedLogs, ::testing::Range<std::size_t>(0, 6), generator_name);

TEST(CalibrationLoads, FiveHertzQuantisedLogWithSecondDifferenceTwiceTheFirst) {
  // A slow drift of 1 mm a sample at 5 Hz, 5 decimals of minutes (1.85 cm): the first
  // differences are 0 or one quantum, the second -1, 0 or +1 quantum: W2 = 2 W1. (Over 60 s,
  // 0.4 m between the first and last tenth: under the motion check's 2 m floor, as a noiseless
  // receiver's wander must be. 60 s rather than 300 s: the same check on a fifth of the data.)
  noise::NoiseConfig none;
  none.model = noise::Model::none;
  const auto drift = [](double t_s) { return Enu{0.005 * t_s, 0.004 * t_s, 0.0}; };
  const std::string log = test::model_log(none, 3, 5.0, 60.0, 5, true, drift);
  const Calibration c = calibrate(read_receiver_log(log), CalibrateOptions{1, 2});
  EXPECT_NEAR(c.cgrw_measured[1].width_d2_m / c.cgrw_measured[1].width_d1_m, 2.0, 1e-6);
  expect_every_model_runs(log, "5 Hz, 5 decimals, W2 = 2 W1");
}

TEST(CalibrationLoads, ConstantAltitudeGivesNoNoiseOnUp) {
  noise::NoiseConfig gm;
  gm.model = noise::Model::gauss_markov;
  gm.gauss_markov_order = 2;
  gm.gauss_markov = {{{0.5, 20}, {0.4, 20}, {1.0, 20}}};
  const std::string log = test::model_log(gm, 4, 5.0, 60.0, 5, /*constant_alt=*/true);
  const Calibration c = calibrate(read_receiver_log(log), CalibrateOptions{1, 2});
  const std::string toml = config_toml(c, "constant.log");
  EXPECT_NE(toml.find("cgrw-up = \"0,0,0,0\""), std::string::npos) << toml;
  // No key writes a rounding residue (1e-9 m) for the up axis, the third of its east,north,up
  // values. (The horizontal means are residues of the series' own mean, ~1e-9 m: not checked.)
  std::istringstream lines(toml);
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] == '#' || std::count(line.begin(), line.end(), ',') != 2) continue;
    const std::string up = line.substr(line.rfind(',') + 1);
    EXPECT_EQ(up.find("e-"), std::string::npos) << "a residue written for the up axis: " << line << "\n" << toml;
  }
  for (const ModelResult& m : c.models) {
    if (m.config.model == noise::Model::chrono) continue;  // one set of parameters for the three axes
    const auto x = simulate(m.config, c.series, 1);
    for (double v : x[2]) ASSERT_LT(std::abs(v), 1e-5) << model_label(m.config);  // curvature of the round trip only
  }
  expect_every_model_runs(log, "constant altitude");
}

}  // namespace calibration_loads_test
}  // namespace
}  // namespace gpsemu::calibration
