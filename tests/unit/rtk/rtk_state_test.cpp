// The RTK state machine's timeline: DGPS at the first MSM, float after float_after_s, fixed after
// a baseline-dependent time, and the documented decay when corrections stop.
#include "emulator/rtk/rtk_state.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace gpsemu::rtk {
namespace {
namespace rtk_state_test {

using Q = nmea::FixQuality;

const BasePosition kBase{42, 4198944.0, 174747.0, 4781886.0, 0.0};

std::array<double, 3> rover_at(double east_offset_m) {
  return {kBase.ecef_x_m, kBase.ecef_y_m + east_offset_m, kBase.ecef_z_m};
}

Rtcm3Message msm() { return decode_rtcm3(encode_msm(1077, 42, 0, 8, 2)); }
Rtcm3Message base_message() { return decode_rtcm3(encode_base_position(kBase, false)); }

// Steps at 1 Hz from 0 to end_s with corrections (base + MSM) every second up to stop_s; returns
// the quality at each second.
std::vector<Q> timeline(RtkState& rtk, double baseline_m, int stop_s, int end_s) {
  std::vector<Q> q;
  for (int t = 0; t <= end_s; ++t) {
    if (t < stop_s) {
      rtk.received(base_message());
      rtk.received(msm());
    }
    q.push_back(rtk.step(t, rover_at(baseline_m)).quality);
  }
  return q;
}

TEST(RtkState, WithoutCorrectionsTheFixIsAutonomous) {
  RtkState rtk;
  const RtkStatus s = rtk.step(0.0, rover_at(0));
  EXPECT_EQ(s.quality, Q::gps);
  EXPECT_FALSE(s.correction_age_s.has_value());
  EXPECT_FALSE(s.station_id.has_value());
}

TEST(RtkState, ConvergesDgpsThenFloatThenFixedOnTheDefaultTimeline) {
  RtkState rtk;  // float after 3 s, fixed after 10 s + 2 s/km: 12 s at 1 km
  const std::vector<Q> q = timeline(rtk, 1000.0, 100, 20);
  for (int t = 0; t < 3; ++t) EXPECT_EQ(q[t], Q::dgps) << t;
  for (int t = 3; t < 12; ++t) EXPECT_EQ(q[t], Q::rtk_float) << t;
  for (int t = 12; t <= 20; ++t) EXPECT_EQ(q[t], Q::rtk_fixed) << t;
}

TEST(RtkState, ALongerBaselineTakesLongerToFix) {
  RtkState near_rtk, far_rtk;
  const std::vector<Q> near_q = timeline(near_rtk, 100.0, 100, 40);
  const std::vector<Q> far_q = timeline(far_rtk, 10000.0, 100, 40);
  EXPECT_EQ(near_q[11], Q::rtk_fixed);  // 10.2 s
  EXPECT_EQ(far_q[29], Q::rtk_float);   // 30 s
  EXPECT_EQ(far_q[30], Q::rtk_fixed);
}

TEST(RtkState, StoppedCorrectionsDecayFixedToFloatToDgpsToAutonomous) {
  RtkState rtk;
  const std::vector<Q> q = timeline(rtk, 0.0, 20, 100);  // last MSM at t = 19
  EXPECT_EQ(q[19], Q::rtk_fixed);
  EXPECT_EQ(q[24], Q::rtk_fixed);  // age 5
  EXPECT_EQ(q[25], Q::rtk_float);  // age 6 > 5
  EXPECT_EQ(q[49], Q::rtk_float);  // age 30
  EXPECT_EQ(q[50], Q::dgps);       // age 31 > 30
  EXPECT_EQ(q[79], Q::dgps);       // age 60
  EXPECT_EQ(q[80], Q::gps);        // age 61 > 60: the DGNSS timeout
}

// A DGNSS-only receiver (an M9N: RtkTimeline::best dgps) is DGPS while the corrections come and
// for the DGNSS timeout after, never float or fixed.
TEST(RtkState, ADgnssOnlyReceiverStaysDgpsUntilTheTimeout) {
  RtkTimeline t;
  t.best = Q::dgps;
  RtkState rtk(t);
  const std::vector<Q> q = timeline(rtk, 0.0, 20, 100);  // last MSM at t = 19
  for (int k = 0; k < 80; ++k) EXPECT_EQ(q[k], Q::dgps) << k;
  EXPECT_EQ(q[80], Q::gps);  // age 61 > 60
}

TEST(RtkState, ReportsAgeAndStationWhileDifferential) {
  RtkState rtk;
  rtk.received(base_message());
  rtk.received(msm());
  (void)rtk.step(10.0, rover_at(0));
  const RtkStatus s = rtk.step(12.5, rover_at(0));
  ASSERT_TRUE(s.correction_age_s.has_value());
  EXPECT_DOUBLE_EQ(*s.correction_age_s, 2.5);
  EXPECT_EQ(s.station_id, 42);
  ASSERT_TRUE(s.baseline_m.has_value());
  EXPECT_NEAR(*s.baseline_m, 0.0, 1e-9);
}

TEST(RtkState, AfterLosingTheFloatItConvergesAgainFromTheNextMsm) {
  RtkState rtk;
  for (int t = 0; t < 20; ++t) {
    rtk.received(base_message());
    rtk.received(msm());
    (void)rtk.step(t, rover_at(0));
  }
  EXPECT_EQ(rtk.step(55, rover_at(0)).quality, Q::dgps);  // age 36
  rtk.received(msm());
  EXPECT_EQ(rtk.step(56, rover_at(0)).quality, Q::dgps);
  rtk.received(msm());
  EXPECT_EQ(rtk.step(59, rover_at(0)).quality, Q::rtk_float);
  rtk.received(msm());
  EXPECT_EQ(rtk.step(66, rover_at(0)).quality, Q::rtk_fixed);
}

TEST(RtkState, AFloatByAgeReturnsToFixedAtTheNextMsm) {
  RtkState rtk;
  (void)timeline(rtk, 0.0, 20, 30);  // age 11 at t = 30: float
  rtk.received(msm());
  EXPECT_EQ(rtk.step(31, rover_at(0)).quality, Q::rtk_fixed);
}

TEST(RtkState, BeyondTheMaximumBaselineOrWithoutABasePositionOnlyDgps) {
  RtkState far_rtk;
  const std::vector<Q> q = timeline(far_rtk, 60000.0, 200, 150);
  EXPECT_EQ(q[150], Q::dgps);
  RtkState no_base;
  for (int t = 0; t < 60; ++t) {
    no_base.received(msm());
    EXPECT_EQ(no_base.step(t, rover_at(0)).quality, Q::dgps);
  }
}

TEST(RtkState, IgnoresInvalidMessages) {
  RtkState rtk;
  Rtcm3Message bad = msm();
  bad.valid = false;
  rtk.received(bad);
  EXPECT_EQ(rtk.step(1, rover_at(0)).quality, Q::gps);
}

TEST(RtkTimelineValidation, NamesTheFieldAndRange) {
  RtkTimeline t;
  t.fix_base_s = 1.0;  // below float_after_s
  try {
    validate(t);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("seconds to fixed: expected seconds >= the seconds to float"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(validate(RtkTimeline{}));
}

}  // namespace rtk_state_test
}  // namespace
}  // namespace gpsemu::rtk
