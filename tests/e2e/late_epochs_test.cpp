// An epoch whose time has passed is skipped and counted, never sent late with its old time stamp
// (docs/replay-and-clocks.md "Timing"; issue 22 point 5). The binary at 10 Hz on stdout is stopped
// with SIGSTOP for 2 s, as a starved or suspended process is, then continued: every RMC that comes
// out reaches the reader within a fraction of a second of its own time (the epoch the loop was
// waiting on when it was stopped is not sent 2 s late), and the summary counts the skipped epochs.
#include <gtest/gtest.h>

#include <csignal>
#include <chrono>
#include <cmath>
#include <regex>
#include <string>
#include <thread>

#include "tests/support/nmea_check.hpp"
#include "tests/support/process.hpp"

namespace gpsemu {
namespace {
namespace late_epochs_test {

using namespace std::chrono_literals;
using test::pump_for;
using test::seconds_of_day;

TEST(LateEpochs, AfterSigstopTheWaitingEpochIsSkippedNotSentWithItsOldTime) {
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--sentences", "RMC", "--talker", "GP", "--output", "stdout",
                        "--log-level", "info"});
  ASSERT_TRUE(gpsemu.wait_for_stderr("first epoch", 10s)) << gpsemu.stderr_text();
  pump_for(gpsemu, 1500ms);
  gpsemu.signal(SIGSTOP);
  std::this_thread::sleep_for(2s);  // the child is stopped: nothing to read meanwhile
  gpsemu.signal(SIGCONT);
  pump_for(gpsemu, 1500ms);
  gpsemu.signal(SIGTERM);
  ASSERT_EQ(gpsemu.wait(10s), 0) << gpsemu.stderr_text();

  // Each RMC's age when the test read it: read time - its own time (seconds of the day).
  std::size_t rmcs = 0;
  double worst_age_s = 0.0;
  std::string worst;
  for (const test::ReadSentence& s : test::sentences_as_read(gpsemu.chunks())) {
    if (test::sentence_type(s.text) != "RMC") continue;
    ++rmcs;
    const double age_s =
        std::fmod(s.read_s - seconds_of_day(test::time_field(s.text)) + 86400.0 + 43200.0, 86400.0) - 43200.0;
    if (age_s > worst_age_s) {
      worst_age_s = age_s;
      worst = s.text;
    }
  }
  EXPECT_GE(rmcs, 20u);
  // 2 s stopped: the stale epoch would be ~2 s old; a fresh one is 50 ms (the latency) plus the
  // reader's own delay on a busy machine.
  EXPECT_LT(worst_age_s, 1.0) << "sent late with its old time: " << worst;

  std::smatch m;
  const std::string err = gpsemu.stderr_text();
  ASSERT_TRUE(std::regex_search(err, m, std::regex("([0-9]+) epochs emitted \\([0-9]+ without fix\\), ([0-9]+) late epochs skipped")))
      << err;
  EXPECT_GE(std::stoul(m[2]), 15u) << "2 s at 10 Hz: about 20 epochs skipped\n" << err;
  EXPECT_EQ(std::stoul(m[1]), rmcs) << "every epoch emitted was read, once";
  std::printf("SIGSTOP 2 s at 10 Hz: %zu RMCs read, worst age %.3f s; %s epochs skipped\n", rmcs, worst_age_s,
              m[2].str().c_str());
}

}  // namespace late_epochs_test
}  // namespace
}  // namespace gpsemu
