// Receiver profiles through the binary (issue 34): `gpsemu profiles` lists every profile of
// data/profiles, `gpsemu profiles NAME` prints the file compiled in, and `gpsemu --profile
// ublox-zed-f9p` is the F9P's calibrated config: its output is the profile file's loaded with
// --config, and over 8 windows of the log's length its sd and first- and second-difference sd
// are within 25% of the real ZED-F9P log's (measured here as calibrate measures a log).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "emulator/calibration/receiver_log.hpp"
#include "emulator/calibration/series_stats.hpp"
#include "tests/support/process.hpp"

namespace gpsemu {
namespace {
namespace profiles_test {

namespace fs = std::filesystem;
const fs::path kProfiles = fs::path(GPSEMU_SOURCE_DIR) / "data" / "profiles";

std::string read_file(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/// The profiles of data/profiles (every NAME.toml but sources.toml).
std::vector<std::string> shipped_profiles() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(kProfiles)) {
    if (entry.path().extension() == ".toml" && entry.path().stem() != "sources") names.push_back(entry.path().stem());
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(Profiles, ListsEveryProfileOfTheRepository) {
  const auto names = shipped_profiles();
  ASSERT_GE(names.size(), 7u);
  const auto r = test::run({GPSEMU_BINARY, "profiles"});
  ASSERT_EQ(r.status, 0) << r.err;
  for (const std::string& name : names) {
    const auto line = r.out.find("\n" + name + " ");
    ASSERT_NE(line, std::string::npos) << name << " is not listed:\n" << r.out;
  }
  EXPECT_TRUE(test::contains(r.out, "\nublox-zed-f9p      ublox-f9p  ublox-zed-f9p_hpg1.11.log")) << r.out;
  EXPECT_TRUE(test::contains(r.out, "SIGMA E/N/U (m)")) << r.out;
}

TEST(Profiles, PrintsTheConfigAProfileStandsFor) {
  for (const std::string& name : shipped_profiles()) {
    const auto r = test::run({GPSEMU_BINARY, "profiles", name});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out, read_file(kProfiles / (name + ".toml"))) << name << ": the binary holds another version (rebuild)";
  }
  const auto bad = test::run({GPSEMU_BINARY, "profiles", "ublox-zed-f10"});
  EXPECT_EQ(bad.status, 2);
  EXPECT_TRUE(test::contains(bad.err, "unknown profile 'ublox-zed-f10'")) << bad.err;
  EXPECT_TRUE(test::contains(bad.err, "ublox-zed-f9p")) << bad.err;
  const auto bad_flag = test::run({GPSEMU_BINARY, "--profile", "nope", "--fast", "--duration", "1", "--output", "stdout"});
  EXPECT_EQ(bad_flag.status, 2);
  EXPECT_TRUE(test::contains(bad_flag.err, "--profile: unknown profile 'nope'")) << bad_flag.err;
}

/// sd, d1 sd and d2 sd of east and north of a log (as calibrate measures it: on its grid, in metres).
std::array<calibration::AxisStats, 2> horizontal_stats(std::span<const double> east, std::span<const double> north,
                                                       double rate_hz) {
  return {calibration::measure_axis(east, rate_hz, east.size()), calibration::measure_axis(north, rate_hz, north.size())};
}

TEST(Profiles, TheF9pProfileRunsAndMatchesTheF9pLog) {
  const std::string log = std::string(GPSEMU_SOURCE_DIR) + "/tests/data/real/ublox-zed-f9p_hpg1.11.log";
  calibration::ReceiverLog real_log = calibration::read_receiver_log_file(log);
  const calibration::EnuSeries real = calibration::to_enu_series(real_log);
  const std::size_t w = real.size();
  ASSERT_EQ(w, 655u);

  const auto by_name = test::run_fast(GPSEMU_BINARY, {"--profile", "ublox-zed-f9p", "--sentences", "RMC,GGA", "--seed", "7",
                                                       "--duration", std::to_string(8 * w)});
  ASSERT_EQ(by_name.status, 0) << by_name.err;
  const auto logged = test::run_fast(GPSEMU_BINARY, {"--profile", "ublox-zed-f9p", "--duration", "1", "--log-level", "info"});
  EXPECT_TRUE(test::contains(logged.err, "profile ublox-zed-f9p: u-blox ZED-F9P")) << logged.err;
  const auto by_file = test::run_fast(GPSEMU_BINARY, {"--config", (kProfiles / "ublox-zed-f9p.toml").string(), "--sentences",
                                                       "RMC,GGA", "--seed", "7", "--duration", std::to_string(8 * w)});
  ASSERT_EQ(by_file.status, 0) << by_file.err;
  EXPECT_TRUE(by_name.out == by_file.out) << "--profile ublox-zed-f9p differs from --config data/profiles/ublox-zed-f9p.toml";

  calibration::ReceiverLog run_log = calibration::read_receiver_log(by_name.out);
  const calibration::EnuSeries run = calibration::to_enu_series(run_log);
  ASSERT_EQ(run.size(), 8 * w);
  EXPECT_EQ(run.minute_decimals, real.minute_decimals);
  const auto want = horizontal_stats(real.axis_m[0], real.axis_m[1], real.rate_hz);
  std::array<std::array<std::vector<double>, 3>, 2> got;  // axis, statistic: one value a window
  for (std::size_t k = 0; k < 8; ++k) {
    const auto s = horizontal_stats(std::span(run.axis_m[0]).subspan(k * w, w), std::span(run.axis_m[1]).subspan(k * w, w),
                                    run.rate_hz);
    for (std::size_t a = 0; a < 2; ++a) {
      got[a][0].push_back(s[a].sd_m);
      got[a][1].push_back(s[a].d1_sd_m);
      got[a][2].push_back(s[a].d2_sd_m);
    }
  }
  const char* axes[] = {"east", "north"};
  const char* stats[] = {"sd", "d1 sd", "d2 sd"};
  for (std::size_t a = 0; a < 2; ++a) {
    const double real_value[] = {want[a].sd_m, want[a].d1_sd_m, want[a].d2_sd_m};
    for (std::size_t i = 0; i < 3; ++i) {
      auto v = got[a][i];
      std::sort(v.begin(), v.end());
      const double median = (v[3] + v[4]) / 2;
      EXPECT_NEAR(median / real_value[i], 1.0, 0.25) << axes[a] << " " << stats[i] << ": 8-window median " << median
                                                     << " m, the log " << real_value[i] << " m";
    }
  }
}

}  // namespace profiles_test
}  // namespace
}  // namespace gpsemu
