// The composite's smooth part is the better of gauss-markov-2 and cgrw (issue 16): calibrate fits
// both (each with jitter and jumps), scores them as it scores every model, keeps the lower score,
// writes composite-smooth accordingly and says which won with both scores.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "emulator/calibration/calibrate.hpp"
#include "emulator/calibration/report.hpp"
#include "emulator/config/config.hpp"
#include "emulator/model/noise/cgrw_model.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "tests/support/calibration_logs.hpp"
#include "tests/support/paths.hpp"

namespace gpsemu::calibration {
namespace {
namespace composite_smooth_test {

const ModelResult& composite_of(const Calibration& c) {
  for (const ModelResult& m : c.models)
    if (m.config.model == noise::Model::composite) return m;
  throw std::logic_error("no composite in the calibration");
}

// A receiver whose wander is the cgrw walk, with white jitter and rare jumps on top.
noise::NoiseConfig cgrw_composite() {
  noise::NoiseConfig c;
  c.model = noise::Model::composite;
  c.composite.smooth = noise::CompositeSmooth::cgrw;
  c.cgrw = noise::cgrw_preset(2.0);
  c.composite.axes = {{{0.03, 0.005, 0.4, 30}, {0.03, 0.005, 0.4, 30}, {0.06, 0.0, 0.0, 0.0}}};
  return c;
}

TEST(CompositeSmooth, BothSmoothPartsAreScoredAndTheLowerKept) {
  const std::string log = test::model_log(cgrw_composite(), 3, 1.0, 1200.0, 6);
  const Calibration c = calibrate(read_receiver_log(log), CalibrateOptions{1, 8});
  const Calibration::CompositeChoice& k = c.composite;
  ASSERT_TRUE(std::isfinite(k.cgrw_score)) << "the cgrw smooth part was not fitted";
  const ModelResult& m = composite_of(c);
  // The kept composite is the one with the lower score, and it is the model's own score.
  EXPECT_EQ(m.score, std::min(k.gm2_score, k.cgrw_score));
  EXPECT_EQ(k.smooth, k.cgrw_score < k.gm2_score ? "cgrw" : "gauss-markov-2");
  EXPECT_EQ(m.config.composite.smooth == noise::CompositeSmooth::cgrw, k.smooth == "cgrw");
  // The report names the choice and both scores.
  const std::string report = comparison_table(c);
  EXPECT_NE(report.find("composite: smooth part " + k.smooth), std::string::npos) << report;
  EXPECT_NE(report.find(fmt::format("with gauss-markov-2 {:.3f}", k.gm2_score)), std::string::npos) << report;
  EXPECT_NE(report.find(fmt::format("with cgrw {:.3f}", k.cgrw_score)), std::string::npos) << report;
  // A log made by a cgrw-smooth composite is not always calibrated back to one: the walk's fit
  // matches the log's standard deviations but not its time scale at ten samples as well as
  // gauss-markov-2 does (measured: 0.060 vs 0.140 here), and the score decides.
}

// What calibrate writes is what it scored: the chosen composite, whichever its smooth part, and
// cgrw's own fit under the cgrw-* keys (issue 27: `--noise cgrw` with a composite config ran the
// composite's walk; then the gauss-markov-2 composite was written even where the cgrw one scored
// better: a u-blox M9N's east first differences came out 68% low).
void expect_written_as_scored(const Calibration& c, const std::string& log_name) {
  const std::string toml = config_toml(c, log_name);
  EXPECT_NE(toml.find("# composite: smooth part " + c.composite.smooth), std::string::npos) << toml;
  EXPECT_NE(toml.find("composite-smooth = \"" + c.composite.smooth + "\""), std::string::npos) << toml;
  const ModelResult& m = composite_of(c);
  const Config composite = build_config_from_text(toml, "calibrated.toml", {{"noise", {"composite"}}});
  const noise::NoiseConfig& run = composite.receiver().noise;
  EXPECT_EQ(run.composite.smooth, m.config.composite.smooth);
  EXPECT_NO_THROW((void)noise::make_noise_model(run, 7)) << toml;
  const Config cgrw = build_config_from_text(toml, "calibrated.toml", {{"noise", {"cgrw"}}});
  const ModelResult* cgrw_fit = nullptr;
  for (const ModelResult& r : c.models)
    if (r.config.model == noise::Model::cgrw) cgrw_fit = &r;
  ASSERT_NE(cgrw_fit, nullptr);
  EXPECT_NEAR(cgrw.receiver().noise.cgrw.east.width_m, cgrw_fit->config.cgrw.east.width_m,
              1e-5 * cgrw_fit->config.cgrw.east.width_m) << "the cgrw-* keys are cgrw's own fit";
  if (c.composite.smooth == "cgrw") {
    ASSERT_TRUE(run.composite.smooth_cgrw.has_value()) << toml;
    const std::array<const noise::CgrwAxis*, 3> fitted{&m.config.cgrw.east, &m.config.cgrw.north, &m.config.cgrw.up};
    for (std::size_t a = 0; a < 3; ++a) {
      EXPECT_NEAR((*run.composite.smooth_cgrw)[a].width_m, fitted[a]->width_m, 1e-5 * fitted[a]->width_m) << a;
      EXPECT_NEAR((*run.composite.smooth_cgrw)[a].sigma_d2_m, fitted[a]->sigma_d2_m, 1e-5 * fitted[a]->sigma_d2_m) << a;
    }
    EXPECT_NE(m.config.cgrw.east.width_m, cgrw_fit->config.cgrw.east.width_m) << "the composite's walk has its own scale";
  } else {
    EXPECT_FALSE(run.composite.smooth_cgrw.has_value()) << toml;
  }
}

TEST(CompositeSmooth, TheWrittenConfigLoadsWithTheChosenSmoothPart) {
  const std::string log = test::model_log(cgrw_composite(), 4, 1.0, 1200.0, 6);
  expect_written_as_scored(calibrate(read_receiver_log(log), CalibrateOptions{1, 8}), "made.log");
}

// The Telit HE910 (tests/data/real) is one where the cgrw smooth part scores better, and with seed 4
// and 8 runs it also stays better than the composite refitted through the static hold (0.202 vs
// 0.228; with seeds 1, 5 and 6 the held gauss-markov-2 composite wins by as little).
TEST(CompositeSmooth, AWinningCgrwSmoothPartIsWrittenUnderItsOwnKeys) {
  const Calibration c = calibrate(read_receiver_log_file(std::string(GPSEMU_SOURCE_DIR) + "/tests/data/real/telit-he910.log"),
                                  CalibrateOptions{4, 8});
  ASSERT_EQ(c.composite.smooth, "cgrw") << c.composite.describe();
  expect_written_as_scored(c, "telit-he910.log");
}

// The composite's walk keys go together, and without them the composite's cgrw smooth part is cgrw-*'s.
TEST(CompositeSmooth, CompositeCgrwKeysAreAllThreeOrNone) {
  const std::string base = "noise = \"composite\"\ncomposite-smooth = \"cgrw\"\n";
  EXPECT_FALSE(build_config_from_text(base, "c.toml", {}).receiver().noise.composite.smooth_cgrw.has_value());
  try {
    (void)build_config_from_text(base + "composite-cgrw-east = \"1,0.1,0.1,0.02\"\n", "c.toml", {});
    ADD_FAILURE() << "one composite-cgrw axis was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("composite-cgrw-east, composite-cgrw-north and composite-cgrw-up go together"),
              std::string::npos) << e.what();
  }
  const Config all = build_config_from_text(base + "composite-cgrw-east = \"1,0.1,0.1,0.02\"\n"
                                                   "composite-cgrw-north = \"2,0.1,0.1,0.02\"\n"
                                                   "composite-cgrw-up = \"3,0.2,0.2,0.04\"\n", "c.toml", {});
  ASSERT_TRUE(all.receiver().noise.composite.smooth_cgrw.has_value());
  EXPECT_EQ((*all.receiver().noise.composite.smooth_cgrw)[1].width_m, 2.0);
}

}  // namespace composite_smooth_test
}  // namespace
}  // namespace gpsemu::calibration
