// The receiver's own state: a hot start (a fix at the first solution) has run a second and has
// confirmed time at once; a cold start has no valid time until a satellite is tracked, resolves
// UTC with the first fix and confirms it kConfirmDelay later, with TTFF and msss counted from
// power-up; an outage without satellites invalidates the time again; a reset starts over. The
// clock: the same seed gives the same clock, the bias follows its drift and stays within
// +-0.5 ms through a day, the drift within a TCXO's +-0.5 ppm.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>

#include "emulator/model/receiver_clock.hpp"

namespace gpsemu {
namespace {
namespace receiver_clock_test {

using namespace std::chrono;

const nmea::UtcTime t0 = sys_days{year{2026} / November / 24} + hours{12};

nmea::Fix epoch(milliseconds since, int satellites, bool fix) {
  nmea::Fix f;
  f.time_utc = t0 + since;
  f.satellites_in_view = satellites;
  f.quality = fix ? nmea::FixQuality::gps : nmea::FixQuality::none;
  return f;
}

TEST(ReceiverStatus, HotStartHasRunASecondWithConfirmedTime) {
  ReceiverStatusTracker state(1);
  const auto s = state.at(epoch(0ms, 10, true));
  EXPECT_EQ(s.since_start, kHotStartTtff);
  EXPECT_EQ(s.time_to_first_fix, kHotStartTtff);
  EXPECT_TRUE(s.time.valid);
  EXPECT_TRUE(s.time.resolved);
  EXPECT_TRUE(s.time.confirmed);
}

TEST(ReceiverStatus, ColdStartValidatesResolvesThenConfirmsTime) {
  ReceiverStatusTracker state(1);
  auto s = state.at(epoch(0ms, 0, false));
  EXPECT_FALSE(s.time.valid);
  EXPECT_EQ(s.since_start, 0ms);
  EXPECT_EQ(s.time_to_first_fix, 0ms);
  s = state.at(epoch(5000ms, 2, false));  // satellites, no fix yet
  EXPECT_TRUE(s.time.valid);
  EXPECT_FALSE(s.time.resolved);
  EXPECT_FALSE(s.time.confirmed);
  s = state.at(epoch(28000ms, 8, true));
  EXPECT_EQ(s.time_to_first_fix, 28000ms);
  EXPECT_EQ(s.since_start, 28000ms);
  EXPECT_TRUE(s.time.resolved);
  EXPECT_FALSE(s.time.confirmed);
  s = state.at(epoch(29000ms, 8, true));
  EXPECT_FALSE(s.time.confirmed);
  s = state.at(epoch(30000ms, 8, true));
  EXPECT_TRUE(s.time.confirmed);
  // An outage: nothing tracked, nothing valid; TTFF stays.
  s = state.at(epoch(60000ms, 0, false));
  EXPECT_FALSE(s.time.valid);
  EXPECT_FALSE(s.time.resolved);
  EXPECT_FALSE(s.time.confirmed);
  EXPECT_EQ(s.time_to_first_fix, 28000ms);
  EXPECT_EQ(s.since_start, 60000ms);
  s = state.at(epoch(61000ms, 9, true));
  EXPECT_TRUE(s.time.valid);
  EXPECT_TRUE(s.time.resolved);
  EXPECT_FALSE(s.time.confirmed);
}

TEST(ReceiverStatus, ResetStartsOver) {
  ReceiverStatusTracker state(1);
  (void)state.at(epoch(0ms, 10, true));
  state.restart();
  auto s = state.at(epoch(10000ms, 0, false));
  EXPECT_EQ(s.since_start, 0ms);
  EXPECT_EQ(s.time_to_first_fix, 0ms);
  EXPECT_FALSE(s.time.valid);
  s = state.at(epoch(40000ms, 7, true));
  EXPECT_EQ(s.time_to_first_fix, 30000ms);
}

TEST(ReceiverStatus, ClockIsDeterministicGivenTheSeed) {
  ReceiverClock a(7), b(7), c(8);
  bool differs = false;
  for (int k = 0; k < 100; ++k) {
    const ClockState x = a.step(1000ms, true), y = b.step(1000ms, true), z = c.step(1000ms, true);
    EXPECT_EQ(x.bias_ns, y.bias_ns);
    EXPECT_EQ(x.drift_ns_per_s, y.drift_ns_per_s);
    differs = differs || x.bias_ns != z.bias_ns;
  }
  EXPECT_TRUE(differs);
}

TEST(ReceiverStatus, BiasFollowsTheDriftAndIsSteppedByWholeMilliseconds) {
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    ReceiverClock clock(seed);
    ClockState last = clock.step(0ms, true);
    int steps = 0;
    for (int k = 0; k < 86400; ++k) {
      const ClockState now = clock.step(1000ms, true);
      ASSERT_LE(std::abs(now.bias_ns), 500'000) << seed;
      ASSERT_LE(std::abs(now.drift_ns_per_s), 600) << seed;
      // One second of drift, or that and a 1 ms step.
      const double change = double(now.bias_ns) - last.bias_ns;
      const double unexplained = change - 0.5 * (now.drift_ns_per_s + last.drift_ns_per_s);
      if (std::abs(unexplained) > 5.0) {
        ++steps;
        ASSERT_NEAR(std::abs(unexplained), 1e6, 5.0) << seed << " at " << k;
      }
      last = now;
    }
    // A drift of d ns/s crosses the 1 ms window every 1e6 / |d| seconds.
    EXPECT_LE(steps, 86400 * 600 / 1'000'000 + 2) << seed;
  }
  EXPECT_EQ(ReceiverClock(1).step(1000ms, false).time_accuracy_ns, 1'000'000'000u);
}

}  // namespace receiver_clock_test
}  // namespace
}  // namespace gpsemu
