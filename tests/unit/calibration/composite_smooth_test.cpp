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

namespace gpsemu::calibration {
namespace {

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

TEST(CompositeSmooth, TheWrittenConfigLoadsWithTheChosenSmoothPart) {
  const std::string log = test::model_log(cgrw_composite(), 4, 1.0, 1200.0, 6);
  const Calibration c = calibrate(read_receiver_log(log), CalibrateOptions{1, 8});
  const std::string toml = config_toml(c, "made.log");
  EXPECT_NE(toml.find("# composite: smooth part " + c.composite.smooth), std::string::npos) << toml;
  // The cgrw-* keys are cgrw's own fit (issue 27: `--noise cgrw` with a composite config ran the
  // composite's walk): the composite written is always the gauss-markov-2 one.
  const std::string written = "gauss-markov-2";
  if (c.composite.smooth == "cgrw") {
    EXPECT_NE(toml.find("the cgrw-* keys belong to noise = \"cgrw\""), std::string::npos) << toml;
  }
  EXPECT_NE(toml.find("composite-smooth = \"" + written + "\""), std::string::npos) << toml;
  const Config config = build_config_from_text(toml, "calibrated.toml", {{"noise", {"composite"}}});
  EXPECT_EQ(config.receiver().noise.composite.smooth == noise::CompositeSmooth::cgrw, written == "cgrw");
  EXPECT_NO_THROW((void)noise::make_noise_model(config.receiver().noise, 7)) << toml;
}

}  // namespace
}  // namespace gpsemu::calibration
