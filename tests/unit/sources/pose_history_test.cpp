// The pose history: interpolation at epoch times, extrapolation over the horizon, staleness,
// speed from given velocity or from the track, reordered/flooding/restarting senders, and the
// bounded ring. Times are passed in: no clock.
#include <gtest/gtest.h>

#include <cmath>

#include "emulator/sources/pose_history.hpp"

namespace gpsemu::sources {
namespace {
namespace pose_history_test {

using namespace std::chrono_literals;

const UtcNs kT0 = UtcNs{std::chrono::seconds(1'700'000'000)};

UtcNs at_s(double s) { return kT0 + std::chrono::nanoseconds{std::llround(s * 1e9)}; }

TimedPose pose(double s, Enu p, std::optional<Enu> v = std::nullopt, std::optional<double> t = std::nullopt) {
  return TimedPose{at_s(s), t, p, v, std::nullopt, {}};
}

void expect_near(const Enu& a, const Enu& b, double tol = 1e-9) {
  EXPECT_NEAR(a.east_m, b.east_m, tol);
  EXPECT_NEAR(a.north_m, b.north_m, tol);
  EXPECT_NEAR(a.up_m, b.up_m, tol);
}

TEST(PoseHistory, EmptyHasNoTruth) {
  PoseHistory h;
  EXPECT_FALSE(h.sample(kT0));
  EXPECT_FALSE(h.fresh_at(kT0));
}

TEST(PoseHistory, NoTruthBeforeTheFirstPose) {
  PoseHistory h;
  h.push(pose(1.0, {1, 2, 3}));
  EXPECT_FALSE(h.sample(at_s(0.99)));
  ASSERT_TRUE(h.sample(at_s(1.0)));
  expect_near(h.sample(at_s(1.0))->position_m, {1, 2, 3});
}

TEST(PoseHistory, InterpolatesLinearlyBetweenThePosesAroundTheEpoch) {
  PoseHistory h;
  h.push(pose(0.00, {0, 0, 0}));
  h.push(pose(0.02, {2, 4, -2}));
  h.push(pose(0.04, {4, 8, -4}));
  const auto truth = h.sample(at_s(0.03));
  ASSERT_TRUE(truth);
  expect_near(truth->position_m, {3, 6, -3});
  expect_near(truth->velocity_mps, {100, 200, -100}, 1e-6);  // from the track
}

TEST(PoseHistory, GivenVelocitiesAreInterpolatedAndPreferredOverTheTrack) {
  PoseHistory h;
  h.push(pose(0.0, {0, 0, 0}, Enu{1, 0, 0}));
  h.push(pose(0.1, {5, 5, 0}, Enu{3, 2, 0}));
  const auto truth = h.sample(at_s(0.05));
  ASSERT_TRUE(truth);
  expect_near(truth->velocity_mps, {2, 1, 0});
}

TEST(PoseHistory, TrackSpeedUsesSenderTimesWhenBothPosesHaveThem) {
  PoseHistory h;
  // Arrivals bunched 5 ms apart; the sender says they are 0.1 s apart.
  h.push(pose(0.000, {0, 0, 0}, std::nullopt, 10.0));
  h.push(pose(0.005, {1, 0, 0}, std::nullopt, 10.1));
  const auto truth = h.sample(at_s(0.005));
  ASSERT_TRUE(truth);
  expect_near(truth->velocity_mps, {10, 0, 0}, 1e-6);
}

TEST(PoseHistory, TrackSpeedOnArrivalTimesSkipsBackOverTooShortBaselines) {
  PoseHistory h;  // min_track_baseline 10 ms
  h.push(pose(0.000, {0, 0, 0}));
  h.push(pose(0.004, {0, 0.4, 0}));  // 4 ms: too short alone
  h.push(pose(0.010, {0, 1.0, 0}));
  const auto truth = h.sample(at_s(0.010));
  ASSERT_TRUE(truth);
  expect_near(truth->velocity_mps, {0, 100, 0}, 1e-6);  // over the 10 ms from the first pose
}

TEST(PoseHistory, ExtrapolatesWithTheLastVelocityUpToTheHorizonThenHolds) {
  PoseHistoryOptions o;
  o.horizon = 200ms;
  PoseHistory h(o);
  h.push(pose(0.0, {0, 0, 0}, Enu{1, 2, 0}));
  expect_near(h.sample(at_s(0.1))->position_m, {0.1, 0.2, 0});
  expect_near(h.sample(at_s(0.1))->velocity_mps, {1, 2, 0});
  expect_near(h.sample(at_s(0.2))->position_m, {0.2, 0.4, 0});
  // Beyond the horizon: held where the extrapolation stopped, reported as not moving.
  const auto held = h.sample(at_s(0.7));
  ASSERT_TRUE(held);
  expect_near(held->position_m, {0.2, 0.4, 0});
  expect_near(held->velocity_mps, {0, 0, 0});
}

TEST(PoseHistory, ExtrapolatesWithTheTrackVelocityWhenNoneWasGiven) {
  PoseHistory h;
  h.push(pose(0.0, {0, 0, 0}));
  h.push(pose(0.1, {1, 0, 0}));
  expect_near(h.sample(at_s(0.15))->position_m, {1.5, 0, 0}, 1e-9);
}

TEST(PoseHistory, StaleAfterTheTimeoutAndFreshAgainWhenPosesResume) {
  PoseHistoryOptions o;
  o.timeout = 1s;
  PoseHistory h(o);
  h.push(pose(0.0, {1, 1, 0}));
  EXPECT_TRUE(h.sample(at_s(1.0)));   // exactly the timeout: still a fix
  EXPECT_FALSE(h.sample(at_s(1.001)));
  EXPECT_FALSE(h.fresh_at(at_s(5.0)));
  h.push(pose(5.0, {9, 9, 0}));
  ASSERT_TRUE(h.sample(at_s(5.0)));
  expect_near(h.sample(at_s(5.0))->position_m, {9, 9, 0});
  // Epochs inside the gap stay without a fix: the gap is not bridged by interpolation.
  EXPECT_FALSE(h.sample(at_s(4.9)));
}

TEST(PoseHistory, AGapShorterThanTheTimeoutIsInterpolated) {
  PoseHistory h;
  h.push(pose(0.0, {0, 0, 0}));
  h.push(pose(0.8, {8, 0, 0}));
  expect_near(h.sample(at_s(0.4))->position_m, {4, 0, 0});
}

TEST(PoseHistory, ReorderedOrRepeatedSenderTimesAreRefused) {
  PoseHistory h;
  EXPECT_EQ(h.push(pose(0.00, {0, 0, 0}, std::nullopt, 5.00)), PushResult::accepted);
  EXPECT_EQ(h.push(pose(0.02, {1, 0, 0}, std::nullopt, 5.00)), PushResult::out_of_order);
  EXPECT_EQ(h.push(pose(0.04, {1, 0, 0}, std::nullopt, 4.98)), PushResult::out_of_order);
  EXPECT_EQ(h.size(), 1u);
  expect_near(h.sample(at_s(0.04))->position_m, {0, 0, 0});
}

TEST(PoseHistory, ASenderTimeFarBackIsARestartThatClearsTheHistory) {
  PoseHistory h;
  h.push(pose(0.00, {0, 0, 0}, std::nullopt, 100.0));
  h.push(pose(0.02, {1, 0, 0}, std::nullopt, 100.02));
  EXPECT_EQ(h.push(pose(0.04, {50, 0, 0}, std::nullopt, 0.0)), PushResult::restarted);
  EXPECT_EQ(h.size(), 1u);
  EXPECT_FALSE(h.sample(at_s(0.03)));
  expect_near(h.sample(at_s(0.04))->position_m, {50, 0, 0});
}

TEST(PoseHistory, TheWallClockSteppedBackIsARestart) {
  PoseHistory h;
  h.push(pose(10.0, {0, 0, 0}));
  EXPECT_EQ(h.push(pose(2.0, {1, 0, 0})), PushResult::restarted);
  EXPECT_EQ(h.size(), 1u);
}

TEST(PoseHistory, PosesCloserThanTheMinimumSpacingAreAFlood) {
  PoseHistory h;  // min spacing 0.5 ms
  EXPECT_EQ(h.push(pose(0.0000, {0, 0, 0})), PushResult::accepted);
  EXPECT_EQ(h.push(pose(0.0001, {7, 7, 7})), PushResult::flood);
  EXPECT_EQ(h.push(pose(0.0000, {7, 7, 7})), PushResult::flood);  // same arrival time
  EXPECT_EQ(h.push(pose(0.0006, {1, 0, 0})), PushResult::accepted);
  EXPECT_EQ(h.size(), 2u);
}

TEST(PoseHistory, TheRingKeepsTheNewestPosesAndStaysBounded) {
  PoseHistoryOptions o;
  o.capacity = 16;
  PoseHistory h(o);
  for (int i = 0; i < 100; ++i) h.push(pose(i * 0.01, {static_cast<double>(i), 0, 0}));
  EXPECT_EQ(h.size(), 16u);
  EXPECT_FALSE(h.sample(at_s(0.80)));  // evicted
  expect_near(h.sample(at_s(0.845))->position_m, {84.5, 0, 0}, 1e-6);
  expect_near(h.sample(at_s(0.99))->position_m, {99, 0, 0}, 1e-6);
  expect_near(h.newest().position_m, {99, 0, 0});
}

TEST(PoseHistory, BadOptionsThrow) {
  PoseHistoryOptions o;
  o.capacity = 1;
  EXPECT_THROW(PoseHistory{o}, std::invalid_argument);
  o = {};
  o.timeout = 0s;
  EXPECT_THROW(PoseHistory{o}, std::invalid_argument);
}

TEST(PoseHistory, FiftyHertzCircleSampledAtTenHertzIsWithinAMillimetre) {
  PoseHistory h;
  const double r = 20.0, w = 2.0 / r;
  const auto circle = [&](double s) { return Enu{r * std::sin(w * s), -r * std::cos(w * s), 0.0}; };
  double worst = 0.0;
  for (int i = 0; i <= 500; ++i) {
    const double s = i * 0.02;
    h.push(pose(s, circle(s), Enu{2.0 * std::cos(w * s), 2.0 * std::sin(w * s), 0.0}, s));
    if (i % 5 == 1 && i > 5) {  // an epoch a little before the newest pose, as at 10 Hz with latency
      const double e = s - 0.015;
      const Enu d = h.sample(at_s(e))->position_m - circle(e);
      worst = std::max(worst, std::hypot(d.east_m, d.north_m));
    }
  }
  EXPECT_LT(worst, 0.001);
}

TEST(PoseHistory, AJumpFartherThanAVehicleCanGoIsRefusedAndNotInterpolated) {
  PoseHistory h;  // timeout 1 s
  EXPECT_EQ(h.push(pose(0.00, {0, 0, 0})), PushResult::accepted);
  // 20 ms later 12 000 km away (the other side of the Earth in ENU): refused.
  EXPECT_EQ(h.push(pose(0.02, {0, -6.0e6, -1.0e7})), PushResult::too_fast);
  // Within slack + 10 km/s: a fast vehicle with bunched arrivals is kept.
  EXPECT_EQ(h.push(pose(0.021, {1005, 0, 0})), PushResult::accepted);
  expect_near(h.sample(at_s(0.021))->position_m, {1005, 0, 0});
  // The sender's times, when both poses carry them, set the allowed distance.
  PoseHistory s;
  EXPECT_EQ(s.push(pose(0.0, {0, 0, 0}, std::nullopt, 100.0)), PushResult::accepted);
  EXPECT_EQ(s.push(pose(0.5, {20500, 0, 0}, std::nullopt, 102.0)), PushResult::accepted);  // 2 s of sender time: 21 km allowed
  EXPECT_EQ(s.push(pose(0.6, {23000, 0, 0}, std::nullopt, 102.1)), PushResult::too_fast);
}

TEST(PoseHistory, AJumpAfterTheTimeoutStartsAfreshWithoutInterpolation) {
  PoseHistory h;  // timeout 1 s
  h.push(pose(0.0, {0, 0, 0}));
  EXPECT_EQ(h.push(pose(1.5, {5.0e6, 0, 0})), PushResult::accepted);  // across a gap: never interpolated
  EXPECT_FALSE(h.sample(at_s(1.2)));
  expect_near(h.sample(at_s(1.5))->position_m, {5.0e6, 0, 0});
}

}  // namespace pose_history_test
}  // namespace
}  // namespace gpsemu::sources
