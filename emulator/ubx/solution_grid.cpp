// The navigation solution grid of a u-blox (see solution_grid.hpp).
#include "emulator/ubx/solution_grid.hpp"

#include <algorithm>

#include "emulator/ubx/cfg_legacy.hpp"
#include "emulator/ubx/nav.hpp"

namespace gpsemu::ubx {
namespace {

using std::chrono::nanoseconds;

/// Time since the start of the week `t` falls in, on the reference time system of `time_ref`
/// (GPS: UTC + leap seconds; UTC: UTC), as the receiver aligns its solutions to it.
nanoseconds since_week_start(SolutionTime t, std::uint16_t time_ref) {
  using namespace std::chrono;
  constexpr sys_days gps_epoch{year{1980} / January / 6};
  constexpr nanoseconds week = weeks{1};
  const nanoseconds shift = time_ref == 0 ? nanoseconds{0} : nanoseconds{seconds{gps_leap_seconds}};
  nanoseconds since = (t - time_point_cast<nanoseconds>(gps_epoch)) + shift;
  since %= week;
  if (since < nanoseconds{0}) since += week;
  return since;
}

}  // namespace

std::chrono::milliseconds fastest_solution_period(ReceiverModel model) {
  return facts_of(model).fastest_solution_period;
}

std::chrono::milliseconds solution_period(const Settings& s, ReceiverModel model) {
  return std::max(s.output_period(), fastest_solution_period(model));
}

SolutionTime SolutionGrid::next_after(SolutionTime t) const {
  const nanoseconds p = period;
  const nanoseconds into = since_week_start(t, time_ref) % p;
  // A week is not always a whole number of periods: the grid restarts at the top of each week.
  const nanoseconds week = std::chrono::weeks{1};
  const nanoseconds to_week_end = week - since_week_start(t, time_ref);
  const nanoseconds step = std::min(p - into, to_week_end);
  return t + step;
}

bool SolutionGrid::contains(SolutionTime t) const {
  return since_week_start(t, time_ref) % nanoseconds{period} == nanoseconds{0};
}

SolutionGrid solution_grid(const Settings& s, ReceiverModel model) {
  return {solution_period(s, model), s.time_ref};
}

}  // namespace gpsemu::ubx
