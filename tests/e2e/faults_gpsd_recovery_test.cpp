// The byte-level faults against the real gpsd on a pty (Debian's gpsd; missing is a failure, not a
// skip): a `garble` (every sentence broken) and a `silence` give gpsd nothing for their epochs, and
// gpsd reports mode 3 again from the first epoch after them (the reading client recovers); half
// the sentences garbled still leave it some fixes. What is checked is in the epochs' own times, not
// the wall clock: gpsemu runs on a scaled clock (4x, 20 epochs a second of 200 ms each) and the read
// window is scaled alike. The latency fault, whose subject is when gpsd's reports arrive, is
// faults_gpsd_latency_test.cpp, in real time.
#include <gtest/gtest.h>

#include <cstdint>
#include <iostream>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "tests/support/faults_gpsd_run.hpp"
#include "tests/support/process.hpp"

namespace gpsemu {
namespace {
namespace faults_gpsd_recovery_test {

// 4x: 20 epochs a second on the pty. The fault from 12 s to 14 s of NMEA time, 3 s of wall time
// after the start: gpsd, started once the pty exists, reported its first 3-D fix at +3.6 s of NMEA
// time here (0.9 s of wall time), and a loaded machine gets three times that. 16 s in all.
constexpr double kClockScale = 4.0;
constexpr std::int64_t kFaultFromMs = 12000, kFaultToMs = 14000;

/// gpsd: mode 3 before `from_ms`, no report with a time in [from_ms, to_ms), and mode 3 again for
/// the epoch at to_ms or the next (gpsd recovered at once).
void expect_gap_then_recovery(const test::FaultGpsdRun& run, std::int64_t from_ms, std::int64_t to_ms) {
  ASSERT_GE(run.first_epoch_ms, 0) << run.log;
  const std::map<std::int64_t, int> modes = test::modes_since_start(run);
  ASSERT_FALSE(modes.empty()) << run.log;
  std::optional<std::int64_t> first_before, first_after;
  for (const auto& [ms, mode] : modes) {
    if (ms < from_ms && mode == 3 && !first_before) first_before = ms;
    EXPECT_FALSE(ms >= from_ms && ms < to_ms) << "gpsd reported epoch +" << ms << " ms inside the fault";
    if (ms >= to_ms && mode == 3 && !first_after) first_after = ms;
  }
  ASSERT_TRUE(first_before) << "gpsd reported no mode 3 before the fault (it starts at +" << from_ms << " ms)";
  ASSERT_TRUE(first_after) << "gpsd never reported mode 3 after the fault";
  std::cout << fmt::format("gpsd: mode 3 first at +{} ms, again at +{} ms (the fault was +{} to +{} ms)\n", *first_before,
                           *first_after, from_ms, to_ms);
  EXPECT_LE(*first_after, to_ms + 200) << "gpsd took more than one epoch to recover";
}

TEST(FaultsGpsd, GarbleBreaksEverySentenceAndGpsdRecoversAtTheNextEpoch) {
  const test::FaultGpsdRun run = test::run_faults_with_gpsd(
      "garble", "[[fault]]\nkind = \"garble\"\nat = 12\nduration = 2\nrate = 1\n", 16.0, kClockScale);
  expect_gap_then_recovery(run, kFaultFromMs, kFaultToMs);
  EXPECT_TRUE(test::contains(run.log, "10 epochs garbled")) << run.log;
}

TEST(FaultsGpsd, HalfGarbledSentencesStillLeaveGpsdSomeFixesAndItRecovers) {
  const test::FaultGpsdRun run = test::run_faults_with_gpsd(
      "garble_half", "[[fault]]\nkind = \"garble\"\nat = 12\nduration = 2\nrate = 0.5\n", 16.0, kClockScale);
  ASSERT_GE(run.first_epoch_ms, 0) << run.log;
  int inside = 0, mode3_after = 0;
  for (const auto& [ms, mode] : test::modes_since_start(run)) {
    inside += ms >= kFaultFromMs && ms < kFaultToMs;
    mode3_after += ms >= kFaultToMs && mode == 3;
  }
  EXPECT_GT(inside, 0) << "with half the sentences intact some epochs get through";
  EXPECT_GE(mode3_after, 8) << "gpsd reports the epochs after the fault";
}

TEST(FaultsGpsd, SilenceLeavesGpsdWithoutReportsAndItRecoversAtTheNextEpoch) {
  const test::FaultGpsdRun run = test::run_faults_with_gpsd(
      "silence", "[[fault]]\nkind = \"silence\"\nat = 12\nduration = 2\n", 16.0, kClockScale);
  expect_gap_then_recovery(run, kFaultFromMs, kFaultToMs);
  EXPECT_TRUE(test::contains(run.log, "10 epochs silent")) << run.log;
}

}  // namespace faults_gpsd_recovery_test
}  // namespace
}  // namespace gpsemu
