// The byte-level faults against the real gpsd on a pty: a `garble` (every sentence broken) and a
// `silence` give gpsd nothing for their epochs, and gpsd reports mode 3 again from the first epoch
// after them (the reading client recovers); a `latency` makes gpsd's reports arrive late by the
// delay while their times stay the epochs' own. gpsd missing is a failure, not a skip.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "nmea/parse.hpp"
#include "tests/support/gpsd.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace faults_gpsd_recovery_test {

namespace fs = std::filesystem;
using namespace std::chrono;
using nlohmann::json;

struct Report {
  test::Tpv tpv;
  std::int64_t arrived_ms = 0;  ///< ms of the UTC day the report was read (the system clock)
};

struct GpsdRun {
  std::vector<Report> tpv;      ///< every TPV with a time, in order
  std::int64_t first_epoch_ms = -1;  ///< the first epoch written (ms of the day)
  std::string log;              ///< gpsemu's stderr
};

std::int64_t now_ms_of_day() {
  const auto t = system_clock::now();
  return duration_cast<milliseconds>(t - floor<days>(t)).count();
}

/// gpsemu at 5 Hz with `scenario` for `duration_s` on a pty read by gpsd.
GpsdRun run_with_gpsd(const std::string& name, const std::string& scenario, double duration_s) {
  GpsdRun run;
  const fs::path dir = test::scratch_dir("faults_gpsd", name);
  const fs::path link = dir / "gps", file = dir / "out.nmea";
  const fs::path toml = test::write_file(dir / "scenario.toml", scenario);
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "5", "--seed", "21", "--output", "pty:" + link.string(), "--output",
                        "file:" + file.string(), "--duration", fmt::format("{}", duration_s), "--scenario", toml.string(),
                        "--log-level", "info"});
  test::GpsdWatch gpsd(gpsemu, link, test::GpsdAccess::read_only);
  if (!gpsd.ok()) {
    ADD_FAILURE() << gpsd.error();
    return run;
  }
  test::ReportLines lines;
  test::read_with_deadline(gpsd.socket(), {milliseconds(std::llround(duration_s * 1000.0) + 1500)}, [&](std::string_view chunk) {
    const std::int64_t arrived = now_ms_of_day();  // of the read, the same for every report in it
    lines.feed(chunk, [&](const json& j) {
      if (j["class"] != "TPV") return;
      const test::Tpv t = test::tpv_of(j);
      if (t.time_of_day_ms) run.tpv.push_back({t, arrived});
    });
    return false;
  });
  gpsd.close_client();
  EXPECT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  run.log = gpsemu.stderr_text();
  gpsd.stop();
  nmea::StreamReader reader;
  for (const auto& s : reader.feed(test::read_file(file))) {
    if (s.type != "GGA") continue;
    const auto gga = nmea::parse_gga(s);
    if (gga.ok() && gga->time_of_day) {
      run.first_epoch_ms = gga->time_of_day->count();
      break;
    }
  }
  fs::remove_all(dir);
  return run;
}

/// The TPVs' times after the first epoch (ms) with their modes.
std::map<std::int64_t, int> modes_since_start(const GpsdRun& run) {
  std::map<std::int64_t, int> out;
  for (const Report& r : run.tpv) out[*r.tpv.time_of_day_ms - run.first_epoch_ms] = r.tpv.mode;
  return out;
}

/// gpsd: mode 3 before `from_ms`, no report with a time in [from_ms, to_ms), and mode 3 again for
/// the epoch at to_ms or the next (gpsd recovered at once).
void expect_gap_then_recovery(const GpsdRun& run, std::int64_t from_ms, std::int64_t to_ms) {
  ASSERT_GE(run.first_epoch_ms, 0) << run.log;
  const std::map<std::int64_t, int> modes = modes_since_start(run);
  ASSERT_FALSE(modes.empty()) << run.log;
  bool mode3_before = false;
  std::optional<std::int64_t> first_after;
  for (const auto& [ms, mode] : modes) {
    if (ms < from_ms && mode == 3) mode3_before = true;
    EXPECT_FALSE(ms >= from_ms && ms < to_ms) << "gpsd reported epoch +" << ms << " ms inside the fault";
    if (ms >= to_ms && mode == 3 && !first_after) first_after = ms;
  }
  EXPECT_TRUE(mode3_before);
  ASSERT_TRUE(first_after) << "gpsd never reported mode 3 after the fault";
  std::cout << fmt::format("gpsd: mode 3 again at +{} ms (the fault ended at +{} ms)\n", *first_after, to_ms);
  EXPECT_LE(*first_after, to_ms + 200) << "gpsd took more than one epoch to recover";
}

TEST(FaultsGpsd, GarbleBreaksEverySentenceAndGpsdRecoversAtTheNextEpoch) {
  const GpsdRun run = run_with_gpsd("garble", "[[fault]]\nkind = \"garble\"\nat = 2\nduration = 2\nrate = 1\n", 6.0);
  expect_gap_then_recovery(run, 2000, 4000);
  EXPECT_TRUE(test::contains(run.log, "10 epochs garbled")) << run.log;
}

TEST(FaultsGpsd, HalfGarbledSentencesStillLeaveGpsdSomeFixesAndItRecovers) {
  const GpsdRun run = run_with_gpsd("garble_half", "[[fault]]\nkind = \"garble\"\nat = 2\nduration = 2\nrate = 0.5\n", 6.0);
  ASSERT_GE(run.first_epoch_ms, 0) << run.log;
  int inside = 0, mode3_after = 0;
  for (const auto& [ms, mode] : modes_since_start(run)) {
    inside += ms >= 2000 && ms < 4000;
    mode3_after += ms >= 4000 && mode == 3;
  }
  EXPECT_GT(inside, 0) << "with half the sentences intact some epochs get through";
  EXPECT_GE(mode3_after, 8) << "gpsd reports the epochs after the fault";
}

TEST(FaultsGpsd, SilenceLeavesGpsdWithoutReportsAndItRecoversAtTheNextEpoch) {
  const GpsdRun run = run_with_gpsd("silence", "[[fault]]\nkind = \"silence\"\nat = 2\nduration = 2\n", 6.0);
  expect_gap_then_recovery(run, 2000, 4000);
  EXPECT_TRUE(test::contains(run.log, "10 epochs silent")) << run.log;
}

TEST(FaultsGpsd, LatencyDelaysGpsdsReportsWithTheirTimesUnchanged) {
  const GpsdRun run = run_with_gpsd("latency", "[[fault]]\nkind = \"latency\"\nat = 2\nduration = 2\ndelay_ms = 450\n", 6.0);
  ASSERT_GE(run.first_epoch_ms, 0) << run.log;
  std::vector<std::int64_t> lag_in, lag_out;
  std::set<std::int64_t> times;
  for (const Report& r : run.tpv) {
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

}  // namespace faults_gpsd_recovery_test
}  // namespace
}  // namespace gpsemu
