// Test support for calibration: what calibrate writes is what it scored (issue 27), checked on a
// Calibration and its config_toml: the chosen composite, whichever its smooth part, and cgrw's own
// fit under the cgrw-* keys. Shared by the unit tests (generated logs, a quick calibration) and the
// integration tests (real logs, compare's runs).
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <stdexcept>
#include <string>

#include "emulator/calibration/calibrate.hpp"
#include "emulator/config/config.hpp"
#include "emulator/model/noise/noise_model.hpp"

namespace gpsemu::test {

/// The composite of a calibration (every calibration fits one).
inline const calibration::ModelResult& composite_of(const calibration::Calibration& c) {
  for (const calibration::ModelResult& m : c.models)
    if (m.config.model == noise::Model::composite) return m;
  throw std::logic_error("no composite in the calibration");
}

/// The written config names the chosen smooth part, loads with it, and carries cgrw's own fit under
/// the cgrw-* keys and (a cgrw smooth part) the composite's walk under composite-cgrw-*
/// (`--noise cgrw` with a composite config ran the composite's walk; then the gauss-markov-2
/// composite was written even where the cgrw one scored better: a u-blox M9N's east first
/// differences came out 68% low).
inline void expect_written_as_scored(const calibration::Calibration& c, const std::string& log_name) {
  const std::string toml = calibration::config_toml(c, log_name);
  EXPECT_NE(toml.find("# composite: smooth part " + c.composite.smooth), std::string::npos) << toml;
  EXPECT_NE(toml.find("composite-smooth = \"" + c.composite.smooth + "\""), std::string::npos) << toml;
  const calibration::ModelResult& m = composite_of(c);
  const Config composite = build_config_from_text(toml, "calibrated.toml", {{"noise", {"composite"}}});
  const noise::NoiseConfig& run = composite.receiver().noise;
  EXPECT_EQ(run.composite.smooth, m.config.composite.smooth);
  EXPECT_NO_THROW((void)noise::make_noise_model(run, 7)) << toml;
  const Config cgrw = build_config_from_text(toml, "calibrated.toml", {{"noise", {"cgrw"}}});
  const calibration::ModelResult* cgrw_fit = nullptr;
  for (const calibration::ModelResult& r : c.models)
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

}  // namespace gpsemu::test
