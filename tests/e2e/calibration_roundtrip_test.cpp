// calibrate -> emulate -> calibrate through the real binary: a log made by the emulator is
// calibrated, the written config is loaded with `gpsemu --config` and emulated again with six
// seeds, and the four cgrw statistics per axis of those logs (their mean) are within 30% of the
// first log's (first logs of three seeds, 1 Hz and 10 Hz). Also: the calibrate and compare subcommands' output and errors.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <iostream>
#include <string>
#include <vector>

#include "emulator/calibration/calibrate.hpp"
#include "tests/support/calibration_logs.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu::calibration {
namespace {
namespace calibration_roundtrip_test {

std::string emulate(std::vector<std::string> args) {
  const auto r = test::run_fast(GPSEMU_BINARY, args);
  EXPECT_EQ(r.status, 0) << r.err;
  return r.out;
}

std::string temp_path(const std::string& name) { return (test::scratch_root() / ("gpsemu_" + name)).string(); }

void write_file(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  ASSERT_TRUE(f.good()) << path;
}

std::size_t count(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (auto p = text.find(needle); p != std::string::npos; p = text.find(needle, p + 1)) ++n;
  return n;
}

struct Case {
  double rate_hz;
  int seed;
};
// Printed by gtest (and in CTest's test name) as itself, not as its bytes (tools/lib/test_costs.sh).
void PrintTo(const Case& c, std::ostream* os) { *os << c.rate_hz << " Hz, seed " << c.seed; }

class RoundTrip : public ::testing::TestWithParam<Case> {};

TEST_P(RoundTrip, CgrwParametersComeBackWithin30Percent) {
  const auto [rate, seed] = GetParam();
  // A receiver: the report's cgrw walk stepping at the log's rate (smooth, in reach of the fit),
  // written at 6 decimals of minutes (1.85 mm, well below its second differences). GGA altitude
  // has 0.1 m steps, so the up axis is made 20x larger than east: rounding then adds ~1% to its d2 statistics.
  const std::string samples = rate == 1.0 ? "600" : "1200";
  const std::string duration = rate == 1.0 ? "600" : "120";
  const std::string r = rate == 1.0 ? "1" : "10";
  const std::string log1 = emulate({"--rate", r, "--duration", duration, "--noise", "cgrw",
                                    "--cgrw-east", "2,0.12,0.14,0.022", "--cgrw-north", "1.2,0.08,0.09,0.014",
                                    "--cgrw-up", "40,2.4,2.8,0.44", "--cgrw-rate", r, "--cgrw-window",
                                    duration, "--resolution", "6", "--seed", std::to_string(seed)});
  CalibrateOptions o;
  o.runs = 2;
  const Calibration c1 = calibrate(read_receiver_log(log1), o);
  ASSERT_EQ(c1.series.rate_hz, rate);
  ASSERT_EQ(c1.series.minute_decimals, 6);
  ASSERT_EQ(c1.series.size(), static_cast<std::size_t>(std::stoi(samples)));
  ASSERT_TRUE(c1.cgrw_unusable.empty()) << c1.cgrw_unusable;

  // The written config, as it is, drives the emulator (cgrw chosen on the command line, which
  // overrides the file's best-scoring model), over several seeds; each log is measured as
  // calibrate measures it. One log's widths are one window's extremes (+-15% from run to run),
  // so the comparison is of their mean over the seeds: what the config reproduces.
  const std::string config = temp_path("roundtrip_" + r + "_" + std::to_string(seed) + ".toml");
  write_file(config, config_toml(c1, "first log"));
  constexpr int kRuns = 6;
  std::array<noise::CgrwAxis, 3> got;
  for (auto& g : got) g = {0.0, 0.0, 0.0, 0.0};  // (CgrwAxis{} holds the defaults)
  for (int run = 0; run < kRuns; ++run) {
    const std::string log2 = emulate({"--config", config, "--noise", "cgrw", "--duration", duration, "--seed",
                                      std::to_string(100 * seed + run)});
    EXPECT_EQ(count(log2, "GGA,"), c1.series.size());
    ReceiverLog read = read_receiver_log(log2);
    const EnuSeries s2 = to_enu_series(read);
    EXPECT_EQ(s2.rate_hz, rate);
    EXPECT_EQ(s2.minute_decimals, 6);
    for (std::size_t a = 0; a < 3; ++a) {
      const noise::CgrwAxis m = measure_axis(s2.axis_m[a], s2.rate_hz, c1.window_samples).cgrw;
      got[a].width_m += m.width_m / kRuns, got[a].width_d1_m += m.width_d1_m / kRuns;
      got[a].width_d2_m += m.width_d2_m / kRuns, got[a].sigma_d2_m += m.sigma_d2_m / kRuns;
    }
  }
  const char* axes[] = {"east", "north", "up"};
  std::string errors;
  for (std::size_t a = 0; a < 3; ++a) {
    const auto& want = c1.cgrw_measured[a];
    const auto& g = got[a];
    errors += fmt::format(" {} {:+.0f}% {:+.0f}% {:+.0f}% {:+.0f}%;", axes[a], 100 * (g.width_m / want.width_m - 1),
                          100 * (g.width_d1_m / want.width_d1_m - 1), 100 * (g.width_d2_m / want.width_d2_m - 1),
                          100 * (g.sigma_d2_m / want.sigma_d2_m - 1));
    EXPECT_NEAR(g.width_m / want.width_m, 1.0, 0.3) << axes[a] << " width_m";
    EXPECT_NEAR(g.width_d1_m / want.width_d1_m, 1.0, 0.3) << axes[a] << " width_d1_m";
    EXPECT_NEAR(g.width_d2_m / want.width_d2_m, 1.0, 0.3) << axes[a] << " width_d2_m";
    EXPECT_NEAR(g.sigma_d2_m / want.sigma_d2_m, 1.0, 0.3) << axes[a] << " sigma_d2_m";
  }
  std::cout << "round trip " << rate << " Hz seed " << seed << " (W W1 W2 S2):" << errors << "\n";
  std::remove(config.c_str());
}

INSTANTIATE_TEST_SUITE_P(Rates, RoundTrip,
                         ::testing::Values(Case{1.0, 1}, Case{1.0, 2}, Case{1.0, 3}, Case{10.0, 1},
                                           Case{10.0, 2}, Case{10.0, 3}),
                         [](const auto& info) {
                           return (info.param.rate_hz == 1.0 ? std::string("1Hz") : std::string("10Hz")) +
                                  "_seed" + std::to_string(info.param.seed);
                         });

// The subcommands fit every noise model: seconds in a Release build, a minute or more under the
// sanitizers beside other CPU-bound tests (tests/CMakeLists.txt), so their limit is generous.
constexpr std::chrono::minutes kFitTimeout{4};

TEST(CalibrateCommand, WritesALoadableConfigAndReportsWhatItSkipped) {
  const test::MessyLog made = test::make_log(1.0, 400, 5, true);
  const std::string log = temp_path("messy.nmea"), config = temp_path("messy.toml");
  write_file(log, made.text);
  const auto r = test::run({GPSEMU_BINARY, "calibrate", log, "-o", config, "--runs", "2"}, kFitTimeout);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find(std::to_string(made.no_fix) + " GGA without fix"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(std::to_string(made.bad_checksum) + " bad checksums"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 malformed GGA, 1 repeated times"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("score"), std::string::npos);
  std::ifstream f(config);
  const std::string toml((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  for (const char* key : {"noise = ", "rate = 1", "resolution = 5", "origin = ", "cgrw-east = ", "cgrw-north = ",
                          "cgrw-up = ", "cgrw-rate = 1", "cgrw-window = ", "gaussian-sigma = ", "gm-sigma = ",
                          "gm-tau = ", "gm-order = ", "chrono = "})
    EXPECT_NE(toml.find(key), std::string::npos) << key << " missing in\n" << toml;
  // Loaded as it is, with each model.
  for (const char* model : {"", "cgrw", "chrono", "gaussian", "gauss-markov"}) {
    std::vector<std::string> args{"--config", config, "--duration", "5"};
    if (*model) args.insert(args.end(), {"--noise", model});
    const std::string out = emulate(args);
    EXPECT_EQ(count(out, "GGA,"), 5u) << model;
    EXPECT_NE(out.find(",N,"), std::string::npos) << model;  // a position near 47.5 N
  }
  // Without -o the config goes to stdout, the summary to stderr.
  const auto s = test::run({GPSEMU_BINARY, "calibrate", log, "--runs", "1"}, kFitTimeout);
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_EQ(s.out.rfind("# gpsemu calibrate", 0), 0u) << s.out;
  EXPECT_NE(s.err.find("cgrw statistics"), std::string::npos) << s.err;
  std::remove(log.c_str());
  std::remove(config.c_str());
}

TEST(CompareCommand, PrintsRealAndEveryModelSideBySide) {
  const std::string log = temp_path("compare.nmea"), csv = temp_path("compare.csv");
  write_file(log, test::make_log(1.0, 400, 5, true).text);
  const auto r = test::run({GPSEMU_BINARY, "compare", log, "--runs", "2", "--csv", csv}, kFitTimeout);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* text : {"real", "cgrw", "chrono", "gaussian", "gauss-markov", "gauss-markov-2", "max-min (m)",
                           "std (m)", "d1 std (m)", "lag-1 acf", "lag-10 acf", "adev 1 s (m)", "adev 100 s (m)",
                           "score", "off by more than"})
    EXPECT_NE(r.out.find(text), std::string::npos) << text;
  std::ifstream f(csv);
  std::string header;
  std::getline(f, header);
  EXPECT_EQ(header.rfind("t_s,real_east_m,real_north_m,real_up_m,", 0), 0u) << header;
  int lines = 0;
  for (std::string line; std::getline(f, line);) ++lines;
  EXPECT_EQ(lines, 400);
  std::remove(log.c_str());
  std::remove(csv.c_str());
}

TEST(CalibrateCommand, UnusableLogsExitWithStatus2) {
  const std::string log = temp_path("nofix.nmea");
  write_file(log, "$GPGGA,,,,,,0,,,,M,,M,,*66\r\n\xb5\x62 junk\r\n");
  const auto r = test::run({GPSEMU_BINARY, "calibrate", log}, kFitTimeout);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("usable fixes"), std::string::npos) << r.err;
  const auto missing = test::run({GPSEMU_BINARY, "compare", "/nonexistent/receiver.log"}, kFitTimeout);
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("/nonexistent/receiver.log"), std::string::npos) << missing.err;
  std::remove(log.c_str());
}

TEST(JudgeCommand, PrintsTheTableAndWritesJsonAndPlotFiles) {
  const std::string log = temp_path("judge.nmea"), json = temp_path("judge.json"), dir = temp_path("judge_plots");
  write_file(log, test::make_log(1.0, 300, 5, false).text);
  const auto r = test::run({GPSEMU_BINARY, "judge", log, "--runs", "2", "--json", json, "--plots", dir}, kFitTimeout);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* text : {"NIS mean", "NIS p95", "innov rho1", "pos err m", "real", "composite", "gauss-markov-2"})
    EXPECT_NE(r.out.find(text), std::string::npos) << text << "\n" << r.out;
  std::ifstream f(json);
  const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  for (const char* key : {"\"real\"", "\"models\"", "\"best\"", "\"nis_mean\"", "\"nis_p95\"", "\"innov_rho1\""})
    EXPECT_NE(text.find(key), std::string::npos) << key << "\n" << text;
  for (const char* name : {"/judge_nis.csv", "/judge_summary.csv"}) {
    std::ifstream csv(dir + name);
    std::string header;
    EXPECT_TRUE(std::getline(csv, header)) << name;
    EXPECT_EQ(header.rfind("source,", 0), 0u) << header;
  }
  std::remove(log.c_str());
  std::remove(json.c_str());
}

TEST(CalibrateCommand, ADrivingLogIsRefusedUnlessDetrended) {
  // Issue 16: a sim:circle run (20 m radius, 2 m/s) was calibrated as noise.
  const std::string log = temp_path("circle.nmea");
  write_file(log, emulate({"--source", "sim:circle", "--duration", "300", "--sentences", "GGA"}));
  for (const char* sub : {"calibrate", "compare"}) {
    const auto r = test::run({GPSEMU_BINARY, sub, log, "--runs", "1"}, kFitTimeout);
    EXPECT_EQ(r.status, 2) << sub << r.out;
    EXPECT_NE(r.err.find("net displacement"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("m/s"), std::string::npos) << r.err;
  }
  const auto d = test::run({GPSEMU_BINARY, "calibrate", log, "--runs", "1", "--detrend"}, kFitTimeout);
  EXPECT_EQ(d.status, 0) << d.err;
  EXPECT_NE(d.out.find("# detrended"), std::string::npos) << d.out;
  std::remove(log.c_str());
}

}  // namespace calibration_roundtrip_test
}  // namespace
}  // namespace gpsemu::calibration
