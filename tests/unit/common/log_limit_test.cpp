// The one rate limiter of repeated log lines (emulator/common/log_limit.hpp): at most N lines a second,
// the others counted and reported with the next line let through. Times are fed, not waited for.
#include "emulator/common/log_limit.hpp"

#include <gtest/gtest.h>

namespace gpsemu::transport {
namespace {
namespace log_limit_test {

using namespace std::chrono;
using Clock = LogLimit::Clock;

TEST(LogLimit, LetsNLinesThroughEachSecondAndCountsTheRest) {
  LogLimit limit(3);
  const Clock::time_point t0{seconds(100)};
  int admitted = 0;
  for (int k = 0; k < 100'000; ++k) admitted += limit.admit(t0 + microseconds(k)) ? 1 : 0;  // 0.1 s of a flood
  EXPECT_EQ(admitted, 3);
  EXPECT_EQ(limit.suppressed_total(), 99'997u);
  // The next second lets 3 more through; the first of them reports what was suppressed.
  EXPECT_TRUE(limit.admit(t0 + seconds(1)));
  EXPECT_EQ(limit.take_suppressed(), 99'997u);
  EXPECT_EQ(limit.take_suppressed(), 0u);
  EXPECT_TRUE(limit.admit(t0 + seconds(1) + milliseconds(1)));
  EXPECT_TRUE(limit.admit(t0 + seconds(1) + milliseconds(2)));
  EXPECT_FALSE(limit.admit(t0 + seconds(1) + milliseconds(3)));
  EXPECT_EQ(limit.suppressed_total(), 99'998u);
}

TEST(LogLimit, AFloodOfTwentySecondsWritesAtMostNLinesASecond) {
  LogLimit limit(5);
  const Clock::time_point t0{seconds(7)};
  std::uint64_t admitted = 0;
  for (std::int64_t us = 0; us < 20'000'000; us += 4) admitted += limit.admit(t0 + microseconds(us)) ? 1 : 0;
  EXPECT_EQ(admitted, 100u);  // 5 a second for 20 s, of 5 million events
  EXPECT_EQ(admitted + limit.suppressed_total(), 5'000'000u);
}

TEST(LogLimit, SuppressedNoteNamesTheCount) {
  EXPECT_EQ(suppressed_note(0), "");
  EXPECT_EQ(suppressed_note(1), " (1 similar line suppressed)");
  EXPECT_EQ(suppressed_note(1497), " (1497 similar lines suppressed)");
}

TEST(LogLimit, EveryLimiterAddsToTheProcessCount) {
  const std::uint64_t before = log_lines_suppressed();
  LogLimit a(1), b(1);
  const Clock::time_point t0{seconds(1)};
  for (int k = 0; k < 10; ++k) {
    (void)a.admit(t0);
    (void)b.admit(t0);
  }
  EXPECT_EQ(log_lines_suppressed() - before, 18u);
}

}  // namespace log_limit_test
}  // namespace
}  // namespace gpsemu::transport
