// The second-stage faults through the binary in --fast: a scenario of sky-mask, spoof, time and
// reset gives the same bytes (NMEA and UBX) on every run, and the reset's silence and cold start
// are counted in the summary.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace faults_second_stage_test {

constexpr const char* kScenario = R"(
[[fault]]
kind = "sky-mask"
at = 1
duration = 2
mask = "urban-canyon"
[[fault]]
kind = "spoof"
at = 3
duration = 3
speed_mps = 5
bearing_deg = 45
time_drift_ms_per_s = 10
detected = true
[[fault]]
kind = "time"
mode = "jump"
jump_s = -2.5
at = 6
duration = 2
[[fault]]
kind = "reset"
at = 9
silent_s = 2
ttff_s = 3
)";

TEST(FaultsSecondStage, SameScenarioAndSeedGiveTheSameBytes) {
  const auto dir = test::scratch_dir("faults", "second_stage");
  const auto scenario = test::write_file(dir / "scenario.toml", kScenario);
  const std::vector<std::string> args{"--duration", "16", "--seed", "7", "--scenario", scenario.string(),
                                      "--protocol", "nmea+ubx", "--receiver", "ublox-m9n", "--source", "sim:circle",
                                      "--log-level", "info"};
  const test::Result a = test::run_fast(GPSEMU_BINARY, args);
  const test::Result b = test::run_fast(GPSEMU_BINARY, args);
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_GT(a.out.size(), 10000u);
  EXPECT_TRUE(a.out == b.out);
  EXPECT_TRUE(test::contains(a.err, "fault reset silent_s=2 ttff_s=3 at 9 s for 5 s: 5 epochs")) << a.err;
  EXPECT_TRUE(test::contains(a.err, "2 epochs silent")) << a.err;
  EXPECT_TRUE(test::contains(a.err, "fault spoof speed_mps=5 bearing_deg=45 time_drift_ms_per_s=10 detected at 3 s for 3 s: 3 epochs")) << a.err;
}

}  // namespace faults_second_stage_test
}  // namespace
}  // namespace gpsemu
