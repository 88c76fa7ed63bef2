// A leap second (`time` fault, mode = "leap-second") through the binary on a pty with the real gpsd
// reading it (Debian's gpsd; missing is a failure, not a skip). NMEA: the sentences count
// 235960.00 .. 235960.80 with the old day's date, then 000000.00 of the new day; gpsd (3.22) takes
// second 60 as a POSIX clock does (the next day's 00:00:00, the following second's TPV times
// repeating once) and keeps its 3-D fix through it. UBX: gpsd, configuring the u-blox itself
// (NAV-TIMEGPS on), reports leapseconds 18 up to the leap second and 19 from it on. 5 Hz from a start
// time a few seconds before the event, paced in real time (gpsd reads a live device).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tests/support/gpsd.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace faults_leap_second_test {

namespace fs = std::filesystem;
using namespace std::chrono;
using nlohmann::json;

constexpr const char* kScenario =
    "[[fault]]\nkind = \"time\"\nmode = \"leap-second\"\nleap_utc = \"2026-12-31T23:59:60Z\"\n";

struct LeapRun {
  std::vector<json> tpv;  ///< gpsd's TPVs with a time, in order
  std::string nmea;       ///< the emulator's file copy (NMEA runs)
  std::string log;        ///< gpsemu's stderr
};

/// gpsemu at 5 Hz from `start_time` for `duration_s` with the leap second, on a pty read by gpsd
/// (read-only for NMEA; read-write for UBX, so it turns on the messages it wants).
LeapRun run_with_gpsd(const std::string& name, const std::string& protocol, const std::string& start_time, double duration_s) {
  LeapRun run;
  const fs::path dir = test::scratch_dir("faults_leap", name);
  const fs::path link = dir / "gps", copy = dir / "copy.out";
  const fs::path scenario = test::write_file(dir / "leap.toml", kScenario);
  test::Process gpsemu({GPSEMU_BINARY, "--protocol", protocol, "--output", "pty:" + link.string(), "--output",
                        "file:" + copy.string(), "--rate", "5", "--start-time", start_time, "--clock", "scaled:1",
                        "--duration", fmt::format("{}", duration_s), "--seed", "21", "--scenario", scenario.string(),
                        "--log-level", "info"});
  test::GpsdWatch gpsd(gpsemu, link, protocol == "nmea" ? test::GpsdAccess::read_only : test::GpsdAccess::read_write);
  if (!gpsd.ok()) {
    ADD_FAILURE() << gpsd.error();
    return run;
  }
  gpsd.read_reports(milliseconds(std::llround(duration_s * 1000.0) + 1500), [&](const json& j) {
    if (j["class"] == "TPV" && j.contains("time")) run.tpv.push_back(j);
  });
  gpsd.close_client();
  EXPECT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  gpsd.stop();
  run.log = gpsemu.stderr_text();
  if (protocol == "nmea") run.nmea = test::read_file(copy);
  fs::remove_all(dir);
  return run;
}

/// Field `i` (0: the address) of an NMEA sentence.
std::string field(const std::string& sentence, int i) {
  std::size_t begin = 0;
  for (int k = 0; k < i; ++k) begin = sentence.find(',', begin) + 1;
  const std::size_t end = sentence.find_first_of(",*", begin);
  return sentence.substr(begin, end - begin);
}

TEST(FaultsLeapSecond, NmeaCounts235960WithTheOldDateAndGpsdKeepsItsFixThroughIt) {
  const LeapRun run = run_with_gpsd("nmea", "nmea", "2026-12-31T23:59:57Z", 6.0);
  // The sentences: GGA and RMC times in order, second 60 five times, each time once.
  std::vector<std::string> gga_times;
  std::map<std::string, std::string> rmc_date;  // RMC time -> date
  std::istringstream lines(run.nmea);
  for (std::string line; std::getline(lines, line);) {
    if (line.size() > 6 && line.compare(3, 4, "GGA,") == 0) gga_times.push_back(field(line, 1));
    if (line.size() > 6 && line.compare(3, 4, "RMC,") == 0) rmc_date[field(line, 1)] = field(line, 9);
  }
  ASSERT_EQ(gga_times.size(), 30u) << run.log;
  const std::vector<std::string> expected_60{"235960.00", "235960.20", "235960.40", "235960.60", "235960.80"};
  const auto at = std::find(gga_times.begin(), gga_times.end(), "235960.00");
  ASSERT_NE(at, gga_times.end()) << "no second 60";
  ASSERT_LE(at + 6, gga_times.end());
  EXPECT_EQ(std::vector<std::string>(at, at + 5), expected_60);
  EXPECT_EQ(*(at - 1), "235959.80");
  EXPECT_EQ(*(at + 5), "000000.00") << "then the new day, one second behind the clock";
  EXPECT_EQ(std::set<std::string>(gga_times.begin(), gga_times.end()).size(), gga_times.size()) << "no time twice";
  EXPECT_EQ(rmc_date["235960.40"], "311226") << "RMC's date stays the old day during second 60";
  EXPECT_EQ(rmc_date["235959.00"], "311226");
  EXPECT_EQ(rmc_date["000000.00"], "010127");
  EXPECT_NE(run.log.find("time mode=leap-second leap_utc=2026-12-31T23:59:60Z"), std::string::npos) << run.log;

  // gpsd: a TPV for every epoch from the moment it attached, mode 3 throughout; second 60 read as
  // the next day's 00:00:00 (POSIX), so 00:00:00.x comes twice.
  ASSERT_GE(run.tpv.size(), 15u) << run.log;
  std::map<std::string, int> seen;
  for (std::size_t k = 0; k < run.tpv.size(); ++k) {
    if (k > 0) {  // gpsd's first cycle may be 2-D
      EXPECT_EQ(run.tpv[k].value("mode", 0), 3) << run.tpv[k].dump();
    }
    ++seen[run.tpv[k]["time"].get<std::string>()];
  }
  for (const char* t : {"2027-01-01T00:00:00.000Z", "2027-01-01T00:00:00.400Z", "2027-01-01T00:00:00.800Z"}) {
    EXPECT_EQ(seen[t], 2) << t << ": second 60 and the next second, both 00:00:00 for gpsd";
  }
  EXPECT_EQ(seen["2026-12-31T23:59:59.800Z"], 1);
  EXPECT_EQ(seen["2027-01-01T00:00:01.000Z"], 1);
}

TEST(FaultsLeapSecond, UbxGpsdReportsLeapSeconds18Then19) {
  const LeapRun run = run_with_gpsd("ubx", "ubx", "2026-12-31T23:59:56Z", 8.0);
  // In order: 18 up to the event, 19 from it on (one change), every TPV after gpsd's first a 3-D fix.
  std::vector<int> counts;
  std::vector<std::string> times;
  for (std::size_t k = 0; k < run.tpv.size(); ++k) {
    const json& j = run.tpv[k];
    if (k > 0) {
      EXPECT_EQ(j.value("mode", 0), 3) << j.dump();
    }
    if (!j.contains("leapseconds")) continue;
    counts.push_back(j["leapseconds"].get<int>());
    times.push_back(j["time"].get<std::string>());
  }
  ASSERT_GE(counts.size(), 10u) << run.log;
  const auto first_19 = std::find(counts.begin(), counts.end(), 19);
  ASSERT_NE(first_19, counts.end()) << "gpsd never reported 19";
  ASSERT_NE(first_19, counts.begin()) << "gpsd never reported 18 before the event";
  EXPECT_TRUE(std::all_of(counts.begin(), first_19, [](int c) { return c == 18; }));
  EXPECT_TRUE(std::all_of(first_19, counts.end(), [](int c) { return c == 19; }));
  // The change at the leap second: after gpsd reported the last epoch of 23:59:59 (with 18), and
  // before 00:00:01. gpsd's TPV times inside second 60 are 00:00:00.x (NAV-PVT's sec 60 through
  // mkgmtime) or 23:59:59.x (NAV-TIMEGPS's GPS time less the new 19): both appear.
  const auto change = static_cast<std::size_t>(first_19 - counts.begin());
  const auto last_normal = std::find(times.begin(), times.end(), "2026-12-31T23:59:59.800Z");
  ASSERT_NE(last_normal, times.end()) << "gpsd did not report 23:59:59.800";
  EXPECT_LT(static_cast<std::size_t>(last_normal - times.begin()), change) << "19 before the leap second";
  for (std::size_t k = 0; k < change; ++k) EXPECT_LT(times[k], "2027-01-01T00:00:01") << "18 after the leap second";
  EXPECT_GE(times.back(), "2027-01-01T00:00:02") << "the run went on past the event";
}

}  // namespace faults_leap_second_test
}  // namespace
}  // namespace gpsemu
