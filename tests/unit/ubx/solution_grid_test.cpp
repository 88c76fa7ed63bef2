// The navigation solution grid of a u-blox: measRate x navRate, aligned to the top of the week of
// the reference time (so iTOW is a multiple of the period), at most the model's fastest rate.
#include <gtest/gtest.h>

#include <chrono>

#include "emulator/ubx/nav.hpp"
#include "emulator/ubx/solution_grid.hpp"

namespace gpsemu::ubx {
namespace {
namespace solution_grid_test {

using namespace std::chrono;

SolutionTime at(milliseconds since_midnight) {
  return time_point_cast<nanoseconds>(sys_days{year{2026} / November / 24} + since_midnight);
}

std::uint32_t itow_ms(SolutionTime t) { return gps_time(time_point_cast<milliseconds>(t)).tow_ms; }

Settings with_rate(std::uint16_t meas_ms, std::uint16_t nav_cycles = 1, std::uint16_t time_ref = 1) {
  Settings s;
  s.meas_period_ms = meas_ms;
  s.nav_rate_cycles = nav_cycles;
  s.time_ref = time_ref;
  return s;
}

TEST(UbxSolutionGrid, TwoHundredMillisecondsLieOnTheSecondAndItsFifths) {
  const SolutionGrid grid = solution_grid(with_rate(200), ReceiverModel::ublox_m8n);
  EXPECT_EQ(grid.period, 200ms);
  SolutionTime t = at(12h + 300ms);
  std::vector<milliseconds> seen;
  for (int k = 0; k < 6; ++k) {
    t = grid.next_after(t);
    seen.push_back(duration_cast<milliseconds>(t - at(12h)));
    EXPECT_TRUE(grid.contains(t));
    EXPECT_EQ(itow_ms(t) % 200, 0u);
  }
  EXPECT_EQ(seen, (std::vector<milliseconds>{400ms, 600ms, 800ms, 1000ms, 1200ms, 1400ms}));
  EXPECT_FALSE(grid.contains(at(12h + 100ms)));
}

TEST(UbxSolutionGrid, APeriodNotDividingASecondIsAlignedToTheGpsWeekNotToUtc) {
  // 700 ms: GPS time is UTC + 18 s, and 18 s is no multiple of 700 ms.
  const SolutionGrid gps = solution_grid(with_rate(700), ReceiverModel::generic);
  const SolutionGrid utc = solution_grid(with_rate(700, 1, 0), ReceiverModel::generic);
  SolutionTime t = at(8h);
  for (int k = 0; k < 5; ++k) {
    t = gps.next_after(t);
    EXPECT_EQ(itow_ms(t) % 700, 0u) << k;
  }
  EXPECT_NE(gps.next_after(at(8h)), utc.next_after(at(8h)));
}

TEST(UbxSolutionGrid, NavRateMultipliesTheMeasurementPeriod) {
  EXPECT_EQ(solution_period(with_rate(100, 5), ReceiverModel::ublox_f9p), 500ms);
}

TEST(UbxSolutionGrid, AFasterPeriodThanTheModelNavigatesGivesItsFastestRate) {
  EXPECT_EQ(fastest_solution_period(ReceiverModel::ublox_m8n), 100ms);
  EXPECT_EQ(fastest_solution_period(ReceiverModel::ublox_m9n), 40ms);
  EXPECT_EQ(fastest_solution_period(ReceiverModel::ublox_f9p), 50ms);
  EXPECT_EQ(fastest_solution_period(ReceiverModel::generic), 25ms);
  EXPECT_EQ(solution_period(with_rate(50), ReceiverModel::ublox_m8n), 100ms);
  EXPECT_EQ(solution_period(with_rate(50), ReceiverModel::ublox_f9p), 50ms);
  EXPECT_EQ(solution_period(with_rate(25), ReceiverModel::ublox_m9n), 40ms);
  EXPECT_EQ(solution_period(with_rate(25), ReceiverModel::generic), 25ms);
}

TEST(UbxSolutionGrid, TheGridRestartsAtTheTopOfTheWeek) {
  // 11 s does not divide a week (604 800 s): the last solution of a week is followed by the
  // next week's first second.
  const SolutionGrid grid{11'000ms, 1};
  const SolutionTime week_start = time_point_cast<nanoseconds>(sys_days{year{2026} / November / 22}) - 18s;
  ASSERT_EQ(itow_ms(week_start), 0u);
  const SolutionTime last = week_start - 604'800'000ms % 11'000ms;
  EXPECT_TRUE(grid.contains(last));
  EXPECT_EQ(grid.next_after(last - 1ms), last);
  EXPECT_EQ(grid.next_after(last), week_start);
  EXPECT_TRUE(grid.contains(week_start));
}

}  // namespace solution_grid_test
}  // namespace
}  // namespace gpsemu::ubx
