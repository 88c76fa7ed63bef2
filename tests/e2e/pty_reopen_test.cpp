// Reliability: a client closing and reopening the pty 100 times, staying away 0 to 210 ms between
// visits. Each time it must get one whole epoch of checksum-valid sentences, newer than the one
// before, with no backlog of older epochs queued ahead of it (at most the last one written).
// Afterwards the emulator still runs, holds the same descriptors as before, and a SIGTERM stops it
// with exit status 0 and a summary that counts every epoch as written.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/nmea_check.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace pty_reopen_test {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using test::seconds_of_day;

/// The process's open descriptors: "3 -> /dev/ptmx", one a line, in descriptor order.
std::string open_descriptors(pid_t pid) {
  std::map<int, std::string> fds;
  for (const auto& e : fs::directory_iterator(fs::path("/proc") / std::to_string(pid) / "fd")) {
    std::error_code ec;
    fds[std::stoi(e.path().filename().string())] = fs::read_symlink(e.path(), ec).string();
  }
  std::string out;
  for (const auto& [fd, target] : fds) out += std::to_string(fd) + " -> " + target + "\n";
  return out;
}

/// The state letter in /proc/PID/stat: R, S, ... or Z for a process that has exited.
char process_state(pid_t pid) {
  std::ifstream in(fs::path("/proc") / std::to_string(pid) / "stat");
  std::string stat;
  std::getline(in, stat);
  const auto paren = stat.rfind(')');
  return paren == std::string::npos || paren + 2 >= stat.size() ? '?' : stat[paren + 2];
}

double utc_seconds_of_day_now() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return std::fmod(static_cast<double>(ts.tv_sec) + ts.tv_nsec * 1e-9, 86400.0);
}

/// What one open of the pty delivered.
struct Visit {
  std::vector<std::string> epoch;    ///< the first whole epoch's sentences (RMC .. GLL)
  std::size_t queued_epochs = 0;     ///< RMCs already waiting when the device was opened
  std::size_t invalid = 0;           ///< lines that are not checksum-valid sentences
  std::string before_first_rmc;      ///< bytes ahead of the first RMC (a cut epoch)
  double opened_at_s = 0.0;          ///< UTC seconds of the day when opened
};

/// Takes the first whole epoch (RMC .. GLL) out of `bytes` into `v`; false while there is none.
bool take_whole_epoch(const std::string& bytes, Visit& v) {
  const auto split = test::split_sentences(bytes);
  std::optional<std::size_t> rmc;
  for (std::size_t i = 0; i < split.sentences.size(); ++i) {
    const std::string type = test::sentence_type(split.sentences[i]);
    if (!rmc && type == "RMC") rmc = i;
    if (rmc && type == "GLL") {
      v.epoch.assign(split.sentences.begin() + static_cast<std::ptrdiff_t>(*rmc),
                     split.sentences.begin() + static_cast<std::ptrdiff_t>(i) + 1);
      const auto first_rmc = bytes.find("RMC,");  // "$GNRMC,": the sentence starts 3 bytes earlier
      v.before_first_rmc = bytes.substr(0, first_rmc >= 3 ? first_rmc - 3 : 0);
      for (const auto& s : v.epoch) v.invalid += test::valid_sentence(s) ? 0 : 1;
      return true;
    }
  }
  return false;
}

/// Opens the link, reads until one whole epoch (RMC .. GLL) has arrived or 5 s passed, closes.
Visit visit(const fs::path& link) {
  Visit v;
  v.opened_at_s = utc_seconds_of_day_now();
  const int fd = ::open(link.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return v;
  // One read takes what was queued when the device was opened (an epoch is at most ~800 bytes).
  std::string bytes;
  char buf[16384];
  if (const ssize_t n = ::read(fd, buf, sizeof buf); n > 0) bytes.assign(buf, static_cast<std::size_t>(n));
  for (std::size_t at = bytes.find("RMC,"); at != std::string::npos; at = bytes.find("RMC,", at + 1)) ++v.queued_epochs;
  if (!take_whole_epoch(bytes, v)) {
    test::read_with_deadline(fd, {5s}, [&](std::string_view chunk) {
      bytes.append(chunk);
      return take_whole_epoch(bytes, v);
    });
  }
  ::close(fd);
  return v;
}

TEST(PtyReopenTest, HundredReopensEachGetOneFreshWholeEpochAndLeakNothing) {
  const fs::path dir = test::scratch_root() / ("gpsemu_reopen_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path link = dir / "gps";
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--output", "pty:" + link.string(), "--sentences",
                        "RMC,VTG,GGA,GSA,GSV,GLL", "--talker", "GP", "--log-level", "info"});
  ASSERT_TRUE(gpsemu.wait_for_stderr("pty output: /dev/pts", 10s)) << gpsemu.stderr_text();
  const pid_t pid = gpsemu.pid();
  // The descriptors once the emulator runs its loop (the first epoch has gone out).
  ASSERT_FALSE(visit(link).epoch.empty()) << gpsemu.stderr_text();
  const std::string fds_before = open_descriptors(pid);

  double previous_epoch = -1.0;
  std::size_t most_queued = 0, opens_with_queued = 0;
  for (int i = 0; i < 100; ++i) {
    // Closed for 0, 70, 140 or 210 ms: up to two epochs go out with no client reading them.
    std::this_thread::sleep_for((i % 4) * 70ms);
    const Visit v = visit(link);
    ASSERT_FALSE(v.epoch.empty()) << "open " << i << ": no whole epoch within 5 s\n" << gpsemu.stderr_text();
    EXPECT_EQ(v.invalid, 0u) << "open " << i;
    EXPECT_EQ(v.before_first_rmc, "") << "open " << i << ": the first bytes were not the start of an epoch";
    // One epoch: RMC VTG GGA GSA (one or more) GSV (one or more) GLL, all with RMC's time.
    std::vector<std::string> types;
    for (const auto& s : v.epoch) {
      if (types.empty() || types.back() != test::sentence_type(s)) types.push_back(test::sentence_type(s));
    }
    EXPECT_EQ(types, (std::vector<std::string>{"RMC", "VTG", "GGA", "GSA", "GSV", "GLL"})) << "open " << i;
    const std::string time = test::time_field(v.epoch.front());
    EXPECT_EQ(test::time_field(v.epoch[2]), time) << "open " << i << ": GGA of another epoch";
    // No stale backlog: at most the epoch written last (and the one being written) was queued,
    // every open gets a newer epoch than the last one, and it is today's epoch, not an old one.
    EXPECT_LE(v.queued_epochs, 1u) << "open " << i << ": a backlog of old epochs was waiting";
    most_queued = std::max(most_queued, v.queued_epochs);
    opens_with_queued += v.queued_epochs > 0 ? 1 : 0;
    const double epoch_s = seconds_of_day(time);
    EXPECT_GT(epoch_s, previous_epoch) << "open " << i << ": epoch " << time << " is not newer than the last one";
    previous_epoch = epoch_s;
    const double age_s = std::fmod(v.opened_at_s - epoch_s + 86400.0 + 43200.0, 86400.0) - 43200.0;
    EXPECT_LT(std::abs(age_s), 60.0) << "open " << i << ": epoch " << time << " is not from now";
  }

  // Still running (not a zombie), and no descriptor left behind by 100 clients.
  ASSERT_EQ(::kill(pid, 0), 0);
  EXPECT_NE(process_state(pid), 'Z') << "gpsemu exited\n" << gpsemu.stderr_text();
  const std::string fds_after = open_descriptors(pid);
  EXPECT_EQ(fds_after, fds_before);

  gpsemu.signal(SIGTERM);
  ASSERT_EQ(gpsemu.wait(10s), 0) << gpsemu.stderr_text();
  const std::string err = gpsemu.stderr_text();
  std::smatch emitted, written;
  ASSERT_TRUE(std::regex_search(err, emitted, std::regex("([0-9]+) epochs emitted \\(([0-9]+) without fix\\)"))) << err;
  ASSERT_TRUE(std::regex_search(
      err, written, std::regex("/dev/pts/[0-9]+ \\(link [^)]*\\): ([0-9]+) epochs written \\([0-9]+ bytes\\), "
                               "([0-9]+) dropped, ([0-9]+) failed"))) << err;
  EXPECT_EQ(written[1], emitted[1]);
  EXPECT_EQ(written[2], "0") << "dropped";
  EXPECT_EQ(written[3], "0") << "failed";
  EXPECT_GE(std::stoul(emitted[1]), 100u);  // 100 visits each took a new epoch
  EXPECT_FALSE(fs::exists(fs::symlink_status(link))) << "symlink left behind";
  std::printf("pty reopened 100 times: %s epochs emitted; %zu opens found the last epoch waiting, at most %zu "
              "queued; %zu descriptors before and after\n",
              emitted[1].str().c_str(), opens_with_queued, most_queued,
              static_cast<std::size_t>(std::count(fds_before.begin(), fds_before.end(), '\n')));
  fs::remove_all(dir);
}

}  // namespace pty_reopen_test
}  // namespace
}  // namespace gpsemu
