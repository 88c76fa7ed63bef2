// gpsemu at 5 Hz with a fault scenario on a pty read by the real gpsd (Debian's; missing is a
// failure, not a skip), for the byte-level faults' tests (tests/e2e/faults_gpsd_recovery_test.cpp on
// a scaled clock, tests/e2e/faults_gpsd_latency_test.cpp in real time): every TPV with a time, when
// it was read, and the first epoch's time from the NMEA file gpsemu wrote beside the pty.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "nmea/parse.hpp"
#include "tests/support/gpsd.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu::test {

struct FaultReport {
  Tpv tpv;
  std::int64_t arrived_ms = 0;  ///< ms of the UTC day the report was read (the system clock)
};

struct FaultGpsdRun {
  std::vector<FaultReport> tpv;      ///< every TPV with a time, in order
  std::int64_t first_epoch_ms = -1;  ///< the first epoch written (ms of the day)
  std::string log;                   ///< gpsemu's stderr
};

inline std::int64_t now_ms_of_day() {
  const auto t = std::chrono::system_clock::now();
  return std::chrono::duration_cast<std::chrono::milliseconds>(t - std::chrono::floor<std::chrono::days>(t)).count();
}

/// gpsemu at 5 Hz with `scenario` for `duration_s` of NMEA time on a pty read by gpsd. With
/// `clock_scale` K > 1 the epochs come K times faster than real time (--clock scaled:K, their times
/// still 200 ms apart) and the read window is scaled alike.
inline FaultGpsdRun run_faults_with_gpsd(const std::string& name, const std::string& scenario, double duration_s,
                                         double clock_scale = 1.0) {
  namespace fs = std::filesystem;
  FaultGpsdRun run;
  const fs::path dir = scratch_dir("faults_gpsd", name);
  const fs::path link = dir / "gps", file = dir / "out.nmea";
  const fs::path toml = write_file(dir / "scenario.toml", scenario);
  std::vector<std::string> argv{gpsemu_binary(), "--rate", "5", "--seed", "21", "--output", "pty:" + link.string(),
                                "--output", "file:" + file.string(), "--duration", fmt::format("{}", duration_s),
                                "--scenario", toml.string(), "--log-level", "info"};
  if (clock_scale != 1.0) argv.insert(argv.end(), {"--clock", fmt::format("scaled:{}", clock_scale)});
  Process gpsemu(argv);
  GpsdWatch gpsd(gpsemu, link, GpsdAccess::read_only);
  if (!gpsd.ok()) {
    ADD_FAILURE() << gpsd.error();
    return run;
  }
  const auto window = std::chrono::milliseconds(std::llround(duration_s * 1000.0 / clock_scale) + 1500);
  gpsd.read_reports(window, [&](const nlohmann::json& j) {
    if (j["class"] != "TPV") return;
    const Tpv t = tpv_of(j);
    if (t.time_of_day_ms) run.tpv.push_back({t, now_ms_of_day()});  // as its read is parsed
  });
  gpsd.close_client();
  EXPECT_EQ(gpsemu.wait(std::chrono::seconds(20)), 0) << gpsemu.stderr_text();
  run.log = gpsemu.stderr_text();
  gpsd.stop();
  nmea::StreamReader reader;
  for (const auto& s : reader.feed(read_file(file))) {
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
inline std::map<std::int64_t, int> modes_since_start(const FaultGpsdRun& run) {
  std::map<std::int64_t, int> out;
  for (const FaultReport& r : run.tpv) out[*r.tpv.time_of_day_ms - run.first_epoch_ms] = r.tpv.mode;
  return out;
}

}  // namespace gpsemu::test
