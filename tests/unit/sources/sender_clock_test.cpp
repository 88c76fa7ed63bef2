// The sender clock: where a pose with its own `t` holds outside lockstep. A burst read late holds by
// the sender's spacing, never after its arrival; a constant clock offset is absorbed; drift costs at
// most window x drift; a reordered datagram leaves the estimate alone; a restarted sender starts it
// afresh. Times are passed in: no clock.
#include <gtest/gtest.h>

#include <cmath>

#include "emulator/sources/sender_clock.hpp"

namespace gpsemu::sources {
namespace {
namespace sender_clock_test {

const UtcNs kBase = UtcNs{std::chrono::seconds(1'700'000'000)};

UtcNs utc(double s) { return kBase + std::chrono::nanoseconds{std::llround(s * 1e9)}; }
double seconds_of(UtcNs t) { return std::chrono::duration<double>(t - kBase).count(); }

TEST(SenderClock, ABurstReadLateHoldsBySenderSpacingNotAtTheReadTime) {
  SenderClock clock;
  // 50 Hz poses, each read 1 ms after it was sent; the sender's clock is 1000 s behind ours.
  for (int i = 0; i < 10; ++i) {
    EXPECT_NEAR(seconds_of(clock.place(utc(0.02 * i + 0.001), 0.02 * i - 1000.0)), 0.02 * i + 0.001, 1e-9);
  }
  // gpsemu descheduled 100 ms: the next five poses are all read at 0.300.
  for (int i = 10; i < 15; ++i) {
    EXPECT_NEAR(seconds_of(clock.place(utc(0.300), 0.02 * i - 1000.0)), 0.02 * i + 0.001, 1e-9) << "pose " << i;
  }
}

TEST(SenderClock, APoseNeverHoldsAfterItsArrival) {
  SenderClock clock;
  EXPECT_NEAR(seconds_of(clock.place(utc(1.0), 5.0)), 1.0, 1e-9);
  // Sent "earlier" by its clock than the first suggests (it came through faster): its arrival.
  EXPECT_NEAR(seconds_of(clock.place(utc(1.01), 5.5)), 1.01, 1e-9);
  // ...and from then on the faster path sets the offset.
  EXPECT_NEAR(seconds_of(clock.place(utc(1.2), 5.6)), 1.11, 1e-9);
}

TEST(SenderClock, ADriftingSenderCostsAtMostTheWindowTimesTheDrift) {
  SenderClock clock;  // 0.5 s window
  double worst_s = 0.0;
  for (int i = 0; i < 500; ++i) {
    const double arrival = 0.02 * i;
    const double sent = arrival * 0.99;  // the sender's clock runs 1% slow
    worst_s = std::max(worst_s, arrival - seconds_of(clock.place(utc(arrival), sent)));
  }
  EXPECT_GT(worst_s, 0.004);
  EXPECT_LE(worst_s, 0.005 + 1e-9);
}

TEST(SenderClock, AReorderedDatagramLeavesTheEstimateAndARestartedSenderStartsAfresh) {
  SenderClock clock;
  (void)clock.place(utc(1.000), 10.00);
  (void)clock.place(utc(1.020), 10.02);
  // 10.01 overtaken by 10.02: placed by the estimate (for the history to drop), estimate unchanged.
  EXPECT_NEAR(seconds_of(clock.place(utc(1.025), 10.01)), 1.010, 1e-9);
  EXPECT_NEAR(seconds_of(clock.place(utc(1.040), 10.04)), 1.040, 1e-9);
  // The simulator restarts at t = 0: its poses hold at their arrival again, not 10 s in the past.
  EXPECT_NEAR(seconds_of(clock.place(utc(1.060), 0.0)), 1.060, 1e-9);
  EXPECT_NEAR(seconds_of(clock.place(utc(1.085), 0.02)), 1.080, 1e-9);
}

}  // namespace sender_clock_test
}  // namespace
}  // namespace gpsemu::sources
