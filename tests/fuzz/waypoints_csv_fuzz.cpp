// libFuzzer target for `--source sim:waypoints:FILE` (emulator/sources/waypoints_csv.cpp): the
// bytes as a waypoint CSV through read_waypoints(); an accepted route is then written to a file
// and driven by the simulator's waypoint source (make_sim_source, once and looping). Checks:
//  - the reader throws only std::runtime_error, and its message names the file;
//  - an accepted route is not empty, every position finite and within the limits, every speed in
//    (0, kMaxSpeedMps];
//  - the source's truth is finite at every time sampled, before the start and long after the end.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "emulator/sources/pose_message.hpp"
#include "emulator/sources/sim.hpp"
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
  std::istringstream in(text);
  std::vector<Waypoint> points;
  try {
    points = read_waypoints(in, "fuzz.csv", frame(), 2.0);
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    GPSEMU_FUZZ_CHECK(what.rfind("fuzz.csv:", 0) == 0 || what.find("'fuzz.csv'") != std::string::npos);
    return 0;
  }
  GPSEMU_FUZZ_CHECK(!points.empty());
  for (const Waypoint& w : points) {
    GPSEMU_FUZZ_CHECK(finite(w.position_m) && norm_inf(w.position_m) <= 2.0e7);
    GPSEMU_FUZZ_CHECK(w.speed_mps > 0.0 && w.speed_mps <= kMaxSpeedMps);
  }

  // The route through the real source, which reads a file (removed at exit).
  struct TempFile {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("gpsemu-waypoints-fuzz-" + std::to_string(getpid()) + ".csv");
    ~TempFile() {
      std::error_code ignored;
      std::filesystem::remove(path, ignored);
    }
  };
  static const TempFile temp;
  const std::filesystem::path& file = temp.path;
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << text;
  }
  const UtcNs start = parse_iso8601_utc("2024-05-01T12:00:00Z");
  for (const bool loop : {false, true}) {
    SimOptions options;
    options.loop = loop;
    const auto source = make_sim_source("waypoints:" + file.string(), options, frame(), start);
    (void)source->describe();
    for (const double t_s : {-5.0, 0.0, 0.37, 1.0, 12.5, 100.0, 3600.0, 1e6, 1e9}) {
      const auto truth = source->truth_at(start + std::chrono::nanoseconds(static_cast<std::int64_t>(t_s * 1e9)));
      GPSEMU_FUZZ_CHECK(truth && finite(truth->position_m) && finite(truth->velocity_mps));
      GPSEMU_FUZZ_CHECK(norm_inf(truth->velocity_mps) <= kMaxSpeedMps * 1.000001);
    }
  }
  return 0;
}
