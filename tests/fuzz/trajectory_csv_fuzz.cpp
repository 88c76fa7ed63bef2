// libFuzzer target for `--source replay:FILE.csv` (emulator/sources/trajectory_source.hpp): the
// bytes as a trajectory CSV through read_trajectory_csv(), then the accepted trajectory through
// TrajectorySource. Checks:
//  - the reader throws only std::runtime_error, and its message names the file;
//  - an accepted trajectory has >= 2 rows, strictly increasing times, finite positions and
//    velocities within the documented limits;
//  - the source's truth is finite at and between rows, equal to a row's position at its time, and
//    absent before the first row and after the last.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "emulator/sources/pose_message.hpp"
#include "emulator/sources/trajectory_source.hpp"
#include "emulator/model/time.hpp"
#include "fuzz_check.hpp"
#include "tests/support/enu_checks.hpp"

namespace {

using namespace gpsemu;
using namespace gpsemu::sources;
using namespace gpsemu::test;  // finite, norm_inf, frame (tests/support/enu_checks.hpp)

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const UtcNs first_epoch = parse_iso8601_utc("2024-05-01T12:00:00Z");
  std::istringstream in(text);
  Trajectory trajectory;
  try {
    trajectory = read_trajectory_csv(in, "fuzz.csv", frame(), first_epoch);
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    GPSEMU_FUZZ_CHECK(what.rfind("fuzz.csv:", 0) == 0 || what.find("'fuzz.csv'") != std::string::npos);
    return 0;
  }
  const auto& points = trajectory.points;
  GPSEMU_FUZZ_CHECK(points.size() >= 2 && trajectory.path == "fuzz.csv");
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i > 0) GPSEMU_FUZZ_CHECK(points[i].time > points[i - 1].time);
    // Local metres within 1e7 m; geodetic rows are converted (at most an Earth diameter plus altitude).
    GPSEMU_FUZZ_CHECK(finite(points[i].position_m) && norm_inf(points[i].position_m) <= 2.0e7);
    GPSEMU_FUZZ_CHECK(points[i].velocity_mps.has_value() == points[0].velocity_mps.has_value());
    if (points[i].velocity_mps) {
      GPSEMU_FUZZ_CHECK(finite(*points[i].velocity_mps) && norm_inf(*points[i].velocity_mps) <= kMaxSpeedMps);
    }
  }
  TrajectorySource source(trajectory);
  (void)source.describe();
  const auto one_ns = std::chrono::nanoseconds(1);
  GPSEMU_FUZZ_CHECK(!source.truth_at(points.front().time - one_ns));
  GPSEMU_FUZZ_CHECK(!source.truth_at(points.back().time + one_ns));
  GPSEMU_FUZZ_CHECK(source.ended_at(points.back().time + one_ns) && !source.ended_at(points.back().time));
  const std::size_t step = std::max<std::size_t>(1, points.size() / 64);  // bounded work per input
  for (std::size_t i = 0; i < points.size(); i += step) {
    const auto at_row = source.truth_at(points[i].time);
    GPSEMU_FUZZ_CHECK(at_row && finite(at_row->position_m) && finite(at_row->velocity_mps));
    GPSEMU_FUZZ_CHECK(norm_inf(at_row->position_m - points[i].position_m) <= 1e-6 * (1.0 + norm_inf(points[i].position_m)));
    if (i + 1 < points.size()) {
      const UtcNs mid = points[i].time + (points[i + 1].time - points[i].time) / 2;
      const auto between = source.truth_at(mid);
      GPSEMU_FUZZ_CHECK(between && finite(between->position_m) && finite(between->velocity_mps));
    }
  }
  return 0;
}
