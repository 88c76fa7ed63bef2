// Reliability: SIGTERM, SIGINT, SIGHUP and SIGQUIT shut the emulator down cleanly (exit 0, pty symlink removed,
// every epoch it counted is complete in the file output), and an accelerated soak across UTC
// midnight, month and year ends and 29 February: every consecutive pair of epochs is exactly one
// period apart in RMC's time and date, with none missing or repeated.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace shutdown_soak_test {

namespace fs = std::filesystem;
using namespace std::chrono;

fs::path temp_dir(const std::string& name) { return test::scratch_dir("shutdown", name); }
using test::read_file;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find("\r\n", start)) != std::string::npos; start = end + 2) {
    out.push_back(text.substr(start, end - start));
  }
  return out;
}

std::string field(const std::string& sentence, int index) {
  std::size_t start = 0;
  for (int i = 0; i < index; ++i) start = sentence.find(',', start) + 1;
  return sentence.substr(start, sentence.find_first_of(",*", start) - start);
}

class Shutdown : public ::testing::TestWithParam<int> {};

TEST_P(Shutdown, SignalStopsCleanlyWithSymlinkRemovedAndEveryEpochInTheFile) {
  const int sig = GetParam();
  const auto dir = temp_dir(strsignal(sig));
  const auto link = dir / "gps", file = dir / "out.nmea";
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--output", "pty:" + link.string(),
                        "--output", "file:" + file.string()});
  ASSERT_TRUE(gpsemu.wait_for_stderr("NMEA on file", seconds(10))) << gpsemu.stderr_text();
  ASSERT_TRUE(fs::is_symlink(link));
  // A few epochs go out (nobody reads the pty: the emulator must not care).
  ASSERT_TRUE(gpsemu.wait_for_stderr("no such line", milliseconds(1500)) == std::nullopt);
  gpsemu.signal(sig);
  EXPECT_EQ(gpsemu.wait(seconds(10)), 0) << gpsemu.stderr_text();
  EXPECT_FALSE(fs::exists(fs::symlink_status(link))) << "the pty symlink outlives the emulator";

  const std::string text = read_file(file);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.substr(text.size() - 2), "\r\n") << "the file ends inside a sentence";
  // Every epoch has one RMC; whole epochs only (the file ends with a complete sentence).
  std::size_t epochs = 0;
  for (const auto& l : lines_of(text)) epochs += l.compare(3, 3, "RMC") == 0;
  // The file holds exactly the epochs the emulator says it wrote there: the last one included.
  std::smatch m;
  const std::string err = gpsemu.stderr_text();
  ASSERT_TRUE(std::regex_search(err, m, std::regex("file [^:]*out\\.nmea: ([0-9]+) epochs written"))) << err;
  EXPECT_EQ(std::stoul(m[1].str()), epochs);
  EXPECT_GE(epochs, 5u);
}

// HUP and QUIT shut down like TERM (docs/reliability.md), each in its own run.
INSTANTIATE_TEST_SUITE_P(Signals, Shutdown, ::testing::Values(SIGTERM, SIGINT, SIGHUP, SIGQUIT),
                         [](const auto& info) { return std::string("SIG") + sigabbrev_np(info.param); });

// RMC time "hhmmss.ss" and date "ddmmyy" as UTC milliseconds in the century starting `century`.
sys_time<milliseconds> rmc_time(const std::string& rmc, int century) {
  const std::string t = field(rmc, 1), d = field(rmc, 9);
  const year_month_day date{year{century + std::stoi(d.substr(4, 2))}, month{static_cast<unsigned>(std::stoi(d.substr(2, 2)))},
                            day{static_cast<unsigned>(std::stoi(d.substr(0, 2)))}};
  EXPECT_TRUE(date.ok()) << rmc;
  return sys_days{date} + hours{std::stoi(t.substr(0, 2))} + minutes{std::stoi(t.substr(2, 2))} +
         milliseconds{std::lround(std::stod(t.substr(4)) * 1000.0)};
}

struct Boundary {
  const char* name;
  const char* start;       ///< first epoch, shortly before the boundary
  const char* after_date;  ///< RMC date (ddmmyy) once across
};
// How gtest (and so CTest's test name) prints a case: its name, not its bytes (which change from
// build to build and kept CTest from knowing the test's time: tools/lib/test_costs.sh).
void PrintTo(const Boundary& b, std::ostream* os) { *os << b.name; }

class Soak : public ::testing::TestWithParam<Boundary> {};

TEST_P(Soak, EveryEpochOncePeriodApartAcrossTheBoundary) {
  const Boundary b = GetParam();
  constexpr int kSeconds = 120;  // 1200 epochs at 10 Hz, the boundary 60 s in
  const auto r = test::run({GPSEMU_BINARY, "--fast", "--rate", "10", "--duration", std::to_string(kSeconds),
                            "--start-time", b.start, "--source", "sim:circle",
                            "--output", "stdout", "--log-level", "warn"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::vector<std::string> rmc;
  for (const auto& l : lines_of(r.out)) {
    if (l.compare(3, 3, "RMC") == 0) rmc.push_back(l);
  }
  ASSERT_EQ(rmc.size(), static_cast<std::size_t>(kSeconds * 10));
  const int century = std::stoi(std::string(b.start).substr(0, 2)) * 100;
  for (std::size_t i = 1; i < rmc.size(); ++i) {
    ASSERT_EQ(rmc_time(rmc[i], century) - rmc_time(rmc[i - 1], century), milliseconds(100))
        << "between\n" << rmc[i - 1] << "\n" << rmc[i];
  }
  EXPECT_EQ(field(rmc.back(), 9), b.after_date);
}

INSTANTIATE_TEST_SUITE_P(
    Boundaries, Soak,
    ::testing::Values(Boundary{"midnight", "2024-05-01T23:59:00Z", "020524"},
                      Boundary{"month_end", "2024-04-30T23:59:00Z", "010524"},
                      Boundary{"year_end", "2023-12-31T23:59:00Z", "010124"},
                      Boundary{"into_29_february", "2024-02-28T23:59:00Z", "290224"},
                      Boundary{"out_of_29_february", "2024-02-29T23:59:00Z", "010324"},
                      Boundary{"no_29_february_2023", "2023-02-28T23:59:00Z", "010323"},
                      Boundary{"century_leap_2100_is_not", "2100-02-28T23:59:00Z", "010300"}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace shutdown_soak_test
}  // namespace
}  // namespace gpsemu
