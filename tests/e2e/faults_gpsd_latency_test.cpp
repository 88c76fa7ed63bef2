// The latency fault against the real gpsd on a pty (Debian's gpsd; missing is a failure, not a
// skip): gpsd's reports of the fault's epochs arrive late by its delay while their times stay the
// epochs' own. Its subject is wall-clock time (when a report is read against the epoch's UTC time),
// so it runs in real time, as a timing test (tests/CMakeLists.txt). The garble and silence faults
// are faults_gpsd_recovery_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <iostream>
#include <set>
#include <vector>

#include <fmt/format.h>

#include "tests/support/faults_gpsd_run.hpp"
#include "tests/support/process.hpp"

namespace gpsemu {
namespace {
namespace faults_gpsd_latency_test {

TEST(FaultsGpsd, LatencyDelaysGpsdsReportsWithTheirTimesUnchanged) {
  const test::FaultGpsdRun run = test::run_faults_with_gpsd(
      "latency", "[[fault]]\nkind = \"latency\"\nat = 2\nduration = 2\ndelay_ms = 450\n", 6.0);
  ASSERT_GE(run.first_epoch_ms, 0) << run.log;
  std::vector<std::int64_t> lag_in, lag_out;
  std::set<std::int64_t> times;
  for (const test::FaultReport& r : run.tpv) {
    const std::int64_t ms = *r.tpv.time_of_day_ms - run.first_epoch_ms;
    times.insert(ms);
    (ms >= 2000 && ms < 4000 ? lag_in : lag_out).push_back(r.arrived_ms - *r.tpv.time_of_day_ms);
  }
  ASSERT_GE(lag_in.size(), 5u);
  ASSERT_GE(lag_out.size(), 5u);
  const auto median = [](std::vector<std::int64_t> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  std::cout << fmt::format("gpsd's reports arrived {} ms after their epoch with the latency, {} ms without\n",
                           median(lag_in), median(lag_out));
  EXPECT_GE(median(lag_in), 450);
  EXPECT_LT(median(lag_out), 300);
  for (std::int64_t ms = 2000; ms < 4000; ms += 200) EXPECT_TRUE(times.count(ms)) << "epoch +" << ms << " ms reported";
  EXPECT_TRUE(test::contains(run.log, "10 epochs written late (latency)")) << run.log;
}

}  // namespace faults_gpsd_latency_test
}  // namespace
}  // namespace gpsemu
