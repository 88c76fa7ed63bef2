// Static hold and altitude decimals learnt from a log (emulator/calibration/hold_fit.hpp): a log
// made through the receiver's static hold gives back its share of repeated positions and about its
// radius; a log without hold gets none; the keys written load into the emulator's configuration.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "emulator/calibration/calibrate.hpp"
#include "emulator/calibration/hold_fit.hpp"
#include "emulator/config/config.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/static_hold.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::calibration {
namespace {
namespace hold_fit_test {

noise::NoiseConfig smooth_noise() {
  noise::NoiseConfig c;
  c.model = noise::Model::gauss_markov;
  c.gauss_markov_order = 2;
  c.gauss_markov = {{{0.4, 15}, {0.3, 20}, {0.6, 15}}};
  return c;
}

// GGA at 1 Hz for `seconds` of `config`'s noise through a static hold of `radius_m` (0: none), at
// 6 decimals of minutes and `alt_decimals` decimals of altitude.
std::string held_log(const noise::NoiseConfig& config, double radius_m, int alt_decimals, int seconds) {
  const Geodetic origin{47.5, 8.25, 400.0};
  const LocalFrame frame(origin);
  const auto model = noise::make_noise_model(config, 5);
  StaticHold hold({radius_m, 0.3});
  nmea::FormatOptions f;
  f.minute_decimals = 6;
  f.alt_decimals = alt_decimals;
  const nmea::UtcTime start = std::chrono::sys_days{std::chrono::year{2024} / 5 / 1} + std::chrono::hours(12);
  std::string text;
  for (int k = 0; k < seconds; ++k) {
    const Geodetic g = frame.to_geodetic(hold.apply(model->offset_at(std::chrono::seconds(k)), 0.0));
    nmea::Fix fix;
    fix.time_utc = start + std::chrono::seconds(k);
    fix.quality = nmea::FixQuality::gps;
    fix.dimension = nmea::FixDimension::three_d;
    fix.lat_deg = g.lat_deg, fix.lon_deg = g.lon_deg, fix.alt_msl_m = g.alt_m;
    fix.satellites_used = 9;
    fix.hdop = 0.9;
    text += nmea::format_gga(fix, f);
  }
  return text;
}

TEST(HoldFit, HeldLogGivesBackItsRepeatedShareAndRadius) {
  ReceiverLog log = read_receiver_log(held_log(smooth_noise(), 0.15, 2, 600));
  EXPECT_EQ(log.alt_decimals, 2);
  const EnuSeries s = to_enu_series(log);
  const HoldFit f = fit_hold(s, smooth_noise(), 1, 8);
  EXPECT_GT(f.real_share, 0.5);  // a 0.15 m radius on a smooth 0.3-0.4 m wander holds most epochs
  EXPECT_LT(f.model_share, 0.05);  // 6 decimals of minutes: the model alone hardly ever repeats
  ASSERT_TRUE(f.hold.enabled());
  EXPECT_NEAR(f.held_share, f.real_share, 0.05);
  EXPECT_GT(f.hold.radius_m, 0.15 / 1.5);
  EXPECT_LT(f.hold.radius_m, 0.15 * 1.5);
  EXPECT_FALSE(f.radius_at_bound);

  const Config config = build_config_from_text(hold_toml(f), "calibrated.toml", {});
  EXPECT_DOUBLE_EQ(config.receiver().model.hold.radius_m, std::stod(fmt::format("{:.4g}", f.hold.radius_m)));
  EXPECT_DOUBLE_EQ(config.receiver().model.hold.max_speed_mps, kCalibratedHoldSpeed_mps);
  EXPECT_EQ(config.receiver().format.alt_decimals, 2);
  EXPECT_NE(hold_summary(f).find("hold radius"), std::string::npos) << hold_summary(f);
}

// compare and judge simulate what the emulator runs with the calibrated config: every model through
// the fitted hold, so the best model's runs repeat about as often as the log (without the hold they
// hardly ever do at 6 decimals), and the composite is refitted through it.
TEST(HoldFit, CalibrationSimulatesEveryModelThroughTheFittedHold) {
  CalibrateOptions options;
  options.runs = 2;  // a quick calibration (model_fits.hpp): the hold is fitted and applied as in a full one
  const Calibration c = calibrate(read_receiver_log(held_log(smooth_noise(), 0.15, 2, 150)), options);
  ASSERT_TRUE(c.hold.hold.enabled());
  EXPECT_LT(c.hold.model_share, 0.05);
  for (const ModelResult& m : c.models) {
    const double share = repeat_share(m.first_run_m);
    if (&m == &c.models[c.best]) {
      EXPECT_NEAR(share, c.hold.real_share, 0.2) << model_label(m.config);
    }
    EXPECT_GT(share, 0.1) << model_label(m.config);
  }
  const auto note = std::find_if(c.notes.begin(), c.notes.end(), [](const std::string& n) {
    return n.find("every model simulated through the static hold") != std::string::npos;
  });
  EXPECT_NE(note, c.notes.end());
}

TEST(HoldFit, LogWithoutHoldGetsNone) {
  ReceiverLog log = read_receiver_log(held_log(smooth_noise(), 0.0, 3, 300));
  EXPECT_EQ(log.alt_decimals, 3);
  const HoldFit f = fit_hold(to_enu_series(log), smooth_noise(), 1, 4);
  EXPECT_LT(f.real_share, 0.05);
  EXPECT_FALSE(f.hold.enabled());
  const std::string toml = hold_toml(f);
  EXPECT_EQ(toml.find("hold-radius"), std::string::npos) << toml;
  EXPECT_NE(toml.find("alt-decimals = 3"), std::string::npos) << toml;
}

TEST(HoldFit, RepeatShareCountsPairsOfFixesOnly) {
  const double nan = std::nan("");
  // Pairs of fixes: (0,1) repeats, (1,2) does not, (4,5) repeats; those touching the gap do not count.
  const std::array<std::vector<double>, 3> x{std::vector<double>{1, 1, 2, nan, 5, 5},
                                             std::vector<double>{0, 0, 0, nan, 0, 0}, std::vector<double>(6, 0.0)};
  EXPECT_DOUBLE_EQ(repeat_share(x), 2.0 / 3.0);
}

}  // namespace hold_fit_test
}  // namespace
}  // namespace gpsemu::calibration
