// The whole chain through the real binary with --fast: simulator -> noise -> NMEA text, read
// back with the project's parser and converted to local metres with GeographicLib.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "emulator/model/geo.hpp"
#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/statistics.hpp"

namespace gpsemu {
namespace {
namespace end_to_end_test {

struct Epoch {
  double time_s;  ///< seconds of the day
  Enu position_m;
  double speed_mps;
  std::optional<double> course_deg;
};

const Geodetic kOrigin{43.0725, -89.4125, 260.0};

std::vector<Epoch> run_and_parse(std::vector<std::string> args) {
  const auto r = test::run_fast(GPSEMU_BINARY, args);
  EXPECT_EQ(r.status, 0) << r.err;
  nmea::StreamReader reader;
  const auto sentences = reader.feed(r.out);
  EXPECT_EQ(reader.stats().bad_checksum + reader.stats().malformed + reader.stats().garbage_bytes, 0u);
  const LocalFrame frame(kOrigin);
  std::vector<Epoch> epochs;
  std::map<std::int64_t, nmea::RmcData> rmc_by_time;  // RMC precedes GGA (u-blox order): pair by time
  for (const auto& s : sentences) {
    if (s.type == "GGA") {
      const auto gga = nmea::parse_gga(s);
      EXPECT_TRUE(gga.ok());
      if (!gga.ok() || !gga->lat_deg) continue;
      epochs.push_back({gga->time_of_day->count() / 1000.0,
                        frame.to_enu({*gga->lat_deg, *gga->lon_deg, *gga->alt_msl_m}), 0.0, std::nullopt});
      const auto rmc = rmc_by_time.find(gga->time_of_day->count());
      if (rmc != rmc_by_time.end() && rmc->second.speed_mps) {
        epochs.back().speed_mps = *rmc->second.speed_mps;
        epochs.back().course_deg = rmc->second.course_deg_true;
      }
    } else if (s.type == "RMC") {
      const auto rmc = nmea::parse_rmc(s);
      EXPECT_TRUE(rmc.ok());
      if (rmc.ok() && rmc->time_of_day) rmc_by_time[rmc->time_of_day->count()] = *rmc;
    }
  }
  return epochs;
}

double mean_window_width(const std::vector<double>& x, std::size_t window) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i + window <= x.size(); i += window, ++n) {
    const auto [lo, hi] = std::minmax_element(x.begin() + i, x.begin() + i + window);
    sum += *hi - *lo;
  }
  return sum / n;
}

using test::lag1_autocorrelation;

class StationaryWidth : public ::testing::TestWithParam<double> {};

TEST_P(StationaryWidth, CgrwWandersOverTheConfiguredWidthSmoothly) {
  const double width = GetParam();
  const auto epochs = run_and_parse({"--duration", "3600", "--noise", "cgrw", "--width", std::to_string(width),
                                     "--seed", "11"});
  ASSERT_EQ(epochs.size(), 3600u);
  std::vector<double> east, north;
  for (const auto& e : epochs) {
    east.push_back(e.position_m.east_m);
    north.push_back(e.position_m.north_m);
    EXPECT_LT(e.speed_mps, 0.3);  // the velocity's own error (Doppler), not the wander's derivative
  }
  for (const auto* axis : {&east, &north}) {
    const double w5 = mean_window_width(*axis, 300);
    EXPECT_GT(w5, width / 2.0);
    EXPECT_LT(w5, width * 2.0);
    EXPECT_GT(lag1_autocorrelation(*axis), 0.9);
  }
}

INSTANTIATE_TEST_SUITE_P(Widths, StationaryWidth, ::testing::Values(0.1, 1.0, 10.0));

TEST(EndToEnd, GaussianIsWhite) {
  const auto epochs = run_and_parse({"--duration", "2000", "--noise", "gaussian", "--seed", "5"});
  std::vector<double> east;
  for (const auto& e : epochs) east.push_back(e.position_m.east_m);
  EXPECT_LT(std::abs(lag1_autocorrelation(east)), 0.1);
}

TEST(EndToEnd, CgrwAtOneAndTenHertzAgreePerUnitOfTime) {
  auto stats = [](const std::string& rate) {
    const auto epochs = run_and_parse({"--duration", "3600", "--rate", rate, "--seed", "21", "--resolution", "7"});
    const std::size_t per_s = static_cast<std::size_t>(std::stoi(rate));
    std::vector<double> x, d1;
    for (std::size_t i = 0; i < epochs.size(); ++i) {
      x.push_back(epochs[i].position_m.east_m);
      if (i >= per_s) d1.push_back(epochs[i].position_m.east_m - epochs[i - per_s].position_m.east_m);
    }
    auto sd = [](const std::vector<double>& v) {
      const double m = std::accumulate(v.begin(), v.end(), 0.0) / v.size();
      double s = 0.0;
      for (const double a : v) s += (a - m) * (a - m);
      return std::sqrt(s / v.size());
    };
    return std::pair{sd(x), sd(d1)};
  };
  const auto [sd1, d1_1] = stats("1");
  const auto [sd10, d1_10] = stats("10");
  EXPECT_NEAR(sd10 / sd1, 1.0, 0.3);
  EXPECT_NEAR(d1_10 / d1_1, 1.0, 0.3);
}

TEST(EndToEnd, LineWithoutNoiseIsStraightAndSpeedMatchesDistance) {
  const auto epochs = run_and_parse({"--duration", "30", "--rate", "5", "--source", "sim:line", "--noise", "none",
                                     "--sim-heading", "60", "--sim-speed", "3"});
  ASSERT_EQ(epochs.size(), 150u);
  const double heading = 60.0 * M_PI / 180.0;
  for (std::size_t i = 1; i < epochs.size(); ++i) {
    const auto& p = epochs[i].position_m;
    // Distance from the line through the origin along the heading: within the output resolution.
    EXPECT_NEAR(p.east_m * std::cos(heading) - p.north_m * std::sin(heading), 0.0, 0.02) << i;
    const double moved = std::hypot(p.east_m - epochs[i - 1].position_m.east_m,
                                    p.north_m - epochs[i - 1].position_m.north_m);
    const double dt = epochs[i].time_s - epochs[i - 1].time_s;
    EXPECT_NEAR(dt, 0.2, 1e-9);
    if (epochs[i].time_s < 20.0) {  // driving: RMC speed is the distance covered per second
      EXPECT_NEAR(epochs[i].speed_mps, moved / dt, 0.02 / dt + 0.001) << i;
      EXPECT_NEAR(epochs[i].speed_mps, 3.0, 0.001);
      EXPECT_NEAR(*epochs[i].course_deg, 60.0, 0.01);
    } else if (epochs[i].time_s > 20.0) {  // stopped after 20 s, 60 m out
      EXPECT_LT(moved, 0.03);
      EXPECT_EQ(epochs[i].speed_mps, 0.0);
    }
  }
  EXPECT_NEAR(std::hypot(epochs.back().position_m.east_m, epochs.back().position_m.north_m), 60.0, 0.03);
}

}  // namespace end_to_end_test
}  // namespace
}  // namespace gpsemu
