// The binary's wall clock stepped back 30 s and then ahead 30 s while it runs (issue 22 points 5
// and 6, against the binary; tests/integration/pipeline/clock_step_test.cpp checks the loop
// in-process). The system clock cannot be stepped on a shared machine, so the step is made by
// Debian's libfaketime (package `faketime`, installed by `tools/setup --with-test-deps`),
// preloaded into gpsemu alone: with FAKETIME_TIMESTAMP_FILE and FAKETIME_NO_CACHE it re-reads an
// offset ("+0", "-30") from a file at every clock_gettime(CLOCK_REALTIME), so rewriting the file
// steps the process's wall clock at once; CLOCK_MONOTONIC is left alone
// (FAKETIME_DONT_FAKE_MONOTONIC), as an NTP step leaves it. The loop's wait is an absolute
// CLOCK_REALTIME timerfd, which libfaketime converts to the real clock when it is armed: the
// kernel's timer is not told of the step (no TFD_TIMER_CANCEL_ON_SET wake-up), so it fires at the
// real time of the deadline it was armed for, at most one period later, and the loop looks at the
// (stepped) clock then — the path a real step takes when its cancel arrives late.
//
// Back 30 s at 10 Hz: the step is logged once, and the epochs go on one period apart with
// increasing times (no 30 s of silence). Ahead 30 s: the epochs 30 s late are skipped and counted
// in the summary; nothing is sent with an old time.
#include <gtest/gtest.h>

#include <csignal>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include "tests/support/nmea_check.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace clock_step_faketime_test {

using namespace std::chrono_literals;
using test::pump_for;
using test::seconds_of_day;

const char* const kLibFaketime = "/usr/lib/x86_64-linux-gnu/faketime/libfaketime.so.1";

/// `b - a` in seconds of the day, across midnight.
double day_diff_s(double a, double b) { return std::fmod(b - a + 86400.0 + 43200.0, 86400.0) - 43200.0; }


/// Replaces the offset file in one rename (libfaketime never reads half a file).
void set_offset(const std::filesystem::path& rc, const std::string& offset) {
  const auto tmp = rc.string() + ".new";
  test::write_file(tmp, offset + "\n");
  std::filesystem::rename(tmp, rc);
}

double wall_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

struct Rmc {
  double read_s;  ///< when the test read it (the real clock)
  double time_s;  ///< its own time, seconds of the day
};

TEST(ClockStepFaketime, BackTheOutputGoesOnWithinAPeriodAheadTheLateEpochsAreSkippedAndCounted) {
  ASSERT_TRUE(std::filesystem::exists(kLibFaketime))
      << kLibFaketime << " is missing: install Debian's faketime package (tools/setup --with-test-deps)";
  const auto dir = test::scratch_dir("faketime", "step");
  const auto rc = dir / "faketimerc";
  set_offset(rc, "+0");
  // ASan (the sanitizer stage) insists on coming first among the preloaded libraries; libfaketime
  // goes before it here, which ASan accepts when told not to check. Leaks are not checked in this
  // child (libfaketime's own allocations are not the emulator's; every other e2e test checks them).
  // ASan's allocator reads the clock to pace its release of memory to the OS; under load that read
  // can come while libfaketime 0.9.10 is still initialising, which it reports as "Unexpected
  // recursive calls to clock_gettime()" and then may hang before main() (seen once in CI). The
  // release is turned off in this child, and should libfaketime still report that recursion before
  // gpsemu logs a line, the start is tried once more: the subject here is the step, not libfaketime's
  // start-up. Any other failure to start fails the test at once.
  const char* asan = std::getenv("ASAN_OPTIONS");
  const std::string asan_options = std::string("ASAN_OPTIONS=") + (asan != nullptr && *asan != '\0' ? asan + std::string(":") : "") +
                                   "verify_asan_link_order=0:detect_leaks=0:allocator_release_to_os_interval_ms=-1";
  const auto start = [&] {
    return std::make_unique<test::Process>(std::vector<std::string>{
        "/usr/bin/env", std::string("LD_PRELOAD=") + kLibFaketime, "FAKETIME_TIMESTAMP_FILE=" + rc.string(),
        "FAKETIME_NO_CACHE=1", "FAKETIME_DONT_FAKE_MONOTONIC=1", asan_options, GPSEMU_BINARY, "--rate", "10",
        "--sentences", "RMC", "--talker", "GP", "--output", "stdout", "--log-level", "info"});
  };
  auto child = start();
  bool started = child->wait_for_stderr("first epoch", 10s).has_value();
  if (!started &&
      test::contains(child->stderr_text(), "libfaketime: Unexpected recursive calls") &&
      !test::contains(child->stderr_text(), "gpsemu")) {
    std::printf("libfaketime's start-up recursion before gpsemu's first line; starting once more:\n%s\n",
                child->stderr_text().c_str());
    child->signal(SIGKILL);
    child->wait(5s);
    child = start();
    started = child->wait_for_stderr("first epoch", 10s).has_value();
  }
  test::Process& gpsemu = *child;
  ASSERT_TRUE(started) << gpsemu.stderr_text();
  pump_for(gpsemu, 1000ms);
  const double back_at_s = wall_now_s();
  set_offset(rc, "-30");  // the wall clock goes back 30 s
  pump_for(gpsemu, 2000ms);
  const double ahead_at_s = wall_now_s();
  set_offset(rc, "+0");  // and ahead 30 s again
  pump_for(gpsemu, 1500ms);
  gpsemu.signal(SIGTERM);
  ASSERT_EQ(gpsemu.wait(10s), 0) << gpsemu.stderr_text();
  const std::string err = gpsemu.stderr_text();

  std::vector<Rmc> rmcs;
  for (const test::ReadSentence& s : test::sentences_as_read(gpsemu.chunks())) {
    if (test::sentence_type(s.text) == "RMC") rmcs.push_back({s.read_s, seconds_of_day(test::time_field(s.text))});
  }
  ASSERT_GE(rmcs.size(), 20u) << err;

  // The step back: logged once, counted once.
  EXPECT_TRUE(std::regex_search(err, std::regex("the wall clock went back before epoch .*: its deadlines moved back "
                                                "(29\\.9|30\\.0)[0-9]* s")))
      << err;
  EXPECT_TRUE(test::contains(err, "the wall clock went back 1 time(s)")) << err;

  // Between the two steps: epochs one period apart, times increasing, the longest silence at the
  // reader about a period (30 s without the fix).
  double longest_gap_s = 0.0;
  std::size_t between = 0;
  double jump_s = 0.0;
  for (std::size_t k = 1; k < rmcs.size(); ++k) {
    const double dt = day_diff_s(rmcs[k - 1].time_s, rmcs[k].time_s);
    EXPECT_GT(dt, 0.05) << "an epoch's time went back or repeated at RMC " << k;
    if (rmcs[k].read_s > back_at_s && rmcs[k].read_s < ahead_at_s) {
      ++between;
      EXPECT_NEAR(dt, 0.1, 1e-6) << "RMC " << k << " while the clock was 30 s back";
    }
    if (rmcs[k].read_s > back_at_s && rmcs[k - 1].read_s < ahead_at_s) {
      longest_gap_s = std::max(longest_gap_s, rmcs[k].read_s - rmcs[k - 1].read_s);
    }
    jump_s = std::max(jump_s, dt);
  }
  EXPECT_GE(between, 10u) << "2 s at 10 Hz with the clock 30 s back: about 20 epochs";
  EXPECT_LT(longest_gap_s, 0.6) << "output resumes within a period of the step back (plus a loaded machine's delay)";

  // The step ahead: the epochs it made late are skipped (not sent with their old times) and
  // counted; the output's times jump by the step.
  EXPECT_GT(jump_s, 29.0) << "the epochs the step ahead made late were sent";
  std::smatch m;
  ASSERT_TRUE(std::regex_search(err, m, std::regex("([0-9]+) epochs emitted \\([0-9]+ without fix\\), ([0-9]+) late "
                                                   "epochs skipped")))
      << err;
  EXPECT_GE(std::stoul(m[2]), 290u) << "30 s at 10 Hz: about 300 epochs skipped\n" << err;
  EXPECT_EQ(std::stoul(m[1]), rmcs.size()) << "every epoch emitted was read, once";
  std::printf("figure: clock -30 s then +30 s at 10 Hz under libfaketime: %zu RMCs read, %zu while 30 s back, "
              "longest gap after the step back %.3f s, time jump at the step ahead %.1f s, %s epochs skipped\n",
              rmcs.size(), between, longest_gap_s, jump_s, m[2].str().c_str());
  std::filesystem::remove_all(dir);
}

}  // namespace clock_step_faketime_test
}  // namespace
}  // namespace gpsemu
