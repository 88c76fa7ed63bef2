// Calibration on real receivers' logs (tests/data/real, gpsd's regression logs, BSD-2), the whole
// pipeline at compare's seeds and runs (every model fitted, each simulated 32 times through the NMEA
// formatter and parser: seconds of CPU a log, so an integration test, not a unit test). Reading must
// agree with the logs' independently computed statistics, and the best-scoring model must reproduce
// the standard deviation and the first-difference standard deviation within 25% per horizontal axis.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <string>

#include <fmt/format.h>

#include "emulator/calibration/calibrate.hpp"
#include "tests/support/calibration_written.hpp"
#include "tests/support/paths.hpp"

namespace gpsemu::calibration {
namespace {
namespace real_logs_test {

const std::string kDir = std::string(GPSEMU_SOURCE_DIR) + "/tests/data/real";

struct RealLog {
  const char* file;
  std::size_t fixes;
  int minute_decimals;
  // Independently computed (data/real/README.md): east and north max-min and std (metres).
  double w_east, w_north, sd_east, sd_north;
};
// Printed by gtest (and in CTest's test name) as its file, not as its bytes (tools/lib/test_costs.sh).
void PrintTo(const RealLog& r, std::ostream* os) { *os << r.file; }

class RealLogs : public ::testing::TestWithParam<RealLog> {};

TEST_P(RealLogs, BestModelReproducesSpreadAndFirstDifferences) {
  const RealLog& want = GetParam();
  const std::string path = kDir + "/" + want.file;
  ASSERT_TRUE(std::filesystem::exists(path)) << "real receiver log " << path << " is part of the repository";
  CalibrateOptions options;  // the same seeds and runs as `gpsemu compare`
  const Calibration c = calibrate(read_receiver_log_file(path), options);
  const std::size_t fixes = c.series.size() - c.counts.missing_epochs;
  EXPECT_EQ(fixes, want.fixes);
  EXPECT_EQ(c.series.minute_decimals, want.minute_decimals);
  EXPECT_EQ(c.series.rate_hz, 1.0);
  EXPECT_NEAR(c.real[0].range_m / want.w_east, 1.0, 0.02);
  EXPECT_NEAR(c.real[1].range_m / want.w_north, 1.0, 0.02);
  EXPECT_NEAR(c.real[0].sd_m / want.sd_east, 1.0, 0.02);
  EXPECT_NEAR(c.real[1].sd_m / want.sd_north, 1.0, 0.02);

  const ModelResult& best = c.models[c.best];
  std::string line = fmt::format("{}: best {} (score {:.3f})", want.file, model_label(best.config), best.score);
  const char* axes[] = {"east", "north"};
  for (std::size_t a = 0; a < 2; ++a) {
    const double sd = best.stats[a].sd_m / c.real[a].sd_m;
    const double d1 = best.stats[a].d1_sd_m / c.real[a].d1_sd_m;
    line += fmt::format("; {} std {:.3f}/{:.3f} m ({:+.0f}%), d1 std {:.4f}/{:.4f} m ({:+.0f}%)", axes[a],
                        best.stats[a].sd_m, c.real[a].sd_m, 100 * (sd - 1), best.stats[a].d1_sd_m,
                        c.real[a].d1_sd_m, 100 * (d1 - 1));
    EXPECT_NEAR(sd, 1.0, 0.25) << axes[a] << " std, model " << model_label(best.config);
    EXPECT_NEAR(d1, 1.0, 0.25) << axes[a] << " d1 std, model " << model_label(best.config);
  }
  std::cout << line << "\n";
  // The best model beats white noise by far on a smooth receiver.
  for (const ModelResult& m : c.models)
    if (m.config.model == noise::Model::gaussian) {
      EXPECT_LT(best.score, 0.5 * m.score);
    }
}

// The Telit's first-difference statistics in the README include the 1.7 m jump across its 2 s
// gap; calibration leaves differences across gaps out, so only W and std are compared.
INSTANTIATE_TEST_SUITE_P(
    SharedData, RealLogs,
    ::testing::Values(RealLog{"ublox-zed-f9p_hpg1.11.log", 655, 5, 4.84, 2.24, 1.26, 0.66},
                      RealLog{"telit-he910.log", 186, 4, 4.68, 2.78, 1.18, 0.90},
                      RealLog{"quectel-l76k-dual.log", 130, 5, 1.16, 0.54, 0.38, 0.15}),
    [](const auto& info) {
      std::string name = info.param.file;
      return name.substr(0, name.find_first_of("-_"));
    });

// The Telit HE910 is one where the cgrw smooth part scores better, and with seed 4 and 8 runs it
// also stays better than the composite refitted through the static hold (0.202 vs 0.228; with seeds
// 1, 5 and 6 the held gauss-markov-2 composite wins by as little): what is written is what scored.
TEST(CompositeSmoothOnARealLog, AWinningCgrwSmoothPartIsWrittenUnderItsOwnKeys) {
  const Calibration c = calibrate(read_receiver_log_file(kDir + "/telit-he910.log"), CalibrateOptions{4, 8});
  ASSERT_EQ(c.composite.smooth, "cgrw") << c.composite.describe();
  test::expect_written_as_scored(c, "telit-he910.log");
}

}  // namespace real_logs_test
}  // namespace
}  // namespace gpsemu::calibration
