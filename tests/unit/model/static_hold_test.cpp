// Static hold (emulator/model/static_hold.hpp): the last position repeats while slow and within the
// radius, and is let go beyond the radius, when moving faster, or after a reset.
#include <gtest/gtest.h>

#include "emulator/model/static_hold.hpp"

namespace gpsemu {
namespace {
namespace static_hold_test {

TEST(StaticHold, OffByDefaultReportsEveryPosition) {
  StaticHold hold;
  EXPECT_FALSE(hold.options().enabled());
  EXPECT_DOUBLE_EQ(hold.apply({0.0, 0.0, 0.0}, 0.0).east_m, 0.0);
  EXPECT_DOUBLE_EQ(hold.apply({0.01, 0.0, 0.0}, 0.0).east_m, 0.01);
}

TEST(StaticHold, RepeatsWithinTheRadiusAndLetsGoBeyondIt) {
  StaticHold hold({0.5, 0.3});
  const Enu first = hold.apply({1.0, 2.0, 3.0}, 0.0);
  EXPECT_DOUBLE_EQ(first.east_m, 1.0);
  // 0.4 m away horizontally (the altitude does not count): held, altitude included.
  const Enu near = hold.apply({1.0 + 0.4, 2.0, 3.7}, 0.1);
  EXPECT_DOUBLE_EQ(near.east_m, 1.0);
  EXPECT_DOUBLE_EQ(near.north_m, 2.0);
  EXPECT_DOUBLE_EQ(near.up_m, 3.0);
  // 0.6 m away: the new position is reported and held from then on.
  const Enu far = hold.apply({1.0, 2.6, 3.1}, 0.1);
  EXPECT_DOUBLE_EQ(far.north_m, 2.6);
  EXPECT_DOUBLE_EQ(hold.apply({1.1, 2.5, 3.0}, 0.0).north_m, 2.6);
}

TEST(StaticHold, MovingFasterThanTheThresholdIsNeverHeld) {
  StaticHold hold({10.0, 0.3});
  (void)hold.apply({0.0, 0.0, 0.0}, 0.0);
  EXPECT_DOUBLE_EQ(hold.apply({0.2, 0.0, 0.0}, 0.3).east_m, 0.2);   // at the threshold: not held
  EXPECT_DOUBLE_EQ(hold.apply({0.25, 0.0, 0.0}, 0.29).east_m, 0.2);  // below it again: held
}

TEST(StaticHold, ResetForgetsTheHeldPosition) {
  StaticHold hold({10.0, 0.3});
  (void)hold.apply({0.0, 0.0, 0.0}, 0.0);
  hold.reset();
  EXPECT_DOUBLE_EQ(hold.apply({0.3, 0.0, 0.0}, 0.0).east_m, 0.3);
}

}  // namespace static_hold_test
}  // namespace
}  // namespace gpsemu
