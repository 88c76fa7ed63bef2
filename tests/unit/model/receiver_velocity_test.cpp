// The velocity a receiver reports (emulator/model/receiver.cpp with noise/velocity_noise.hpp): at
// rest a speed like a real receiver's (not 0.000), its sAcc the scatter it applies, a chipset's
// static clamp, the course at rest each chipset family leaves, static hold reporting no motion,
// and --noise none's truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "emulator/model/noise/cgrw_model.hpp"
#include "emulator/model/receiver.hpp"

namespace gpsemu {
namespace {
namespace receiver_velocity_test {

using namespace std::chrono;

const UtcNs kStart = parse_iso8601_utc("2024-05-01T12:00:00Z");
const LocalFrame kFrame({43.0725, -89.4125, 260.0});

UtcNs at(double seconds) { return kStart + nanoseconds{std::llround(seconds * 1e9)}; }

std::unique_ptr<noise::NoiseModel> cgrw() {
  noise::NoiseConfig c;
  c.cgrw = noise::cgrw_preset(1.0);
  return noise::make_noise_model(c, 5);
}

/// The fixes of `seconds` at 1 Hz with the truth `truth(t)`.
template <class TruthAt>
std::vector<nmea::Fix> run(const ReceiverOptions& o, int seconds, TruthAt truth) {
  Receiver rx(kFrame, o, cgrw(), kStart);
  std::vector<nmea::Fix> out;
  for (int k = 0; k < seconds; ++k) out.push_back(rx.fix_at(at(k), truth(k)));
  return out;
}
sources::Truth still(int) { return {}; }

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * (v.size() - 1))];
}

TEST(ReceiverVelocity, AtRestTheSpeedIsAReceiversNotZeroAndSaccIsItsScatter) {
  const ReceiverOptions o;  // the defaults: 0.03 m/s white, 0.02 m/s wander a horizontal axis
  const std::vector<nmea::Fix> fixes = run(o, 3000, still);
  std::vector<double> speeds;
  double sum_sq = 0.0;
  for (const nmea::Fix& f : fixes) {
    ASSERT_TRUE(f.has_fix());
    speeds.push_back(f.speed_mps);
    sum_sq += f.speed_mps * f.speed_mps;
  }
  // A Rayleigh speed of sigma 0.036 m/s an axis: median 0.042, p95 0.088 (real u-blox at rest: 0.02-0.10).
  EXPECT_NEAR(quantile(speeds, 0.5), 0.042, 0.006);
  EXPECT_NEAR(quantile(speeds, 0.95), 0.088, 0.012);
  EXPECT_EQ(std::count(speeds.begin(), speeds.end(), 0.0), 0);
  // sAcc states the RMS of the horizontal speed error, sqrt(2) x the axis sigma (here above the 0.05 floor).
  const double rms = std::sqrt(sum_sq / fixes.size());
  EXPECT_NEAR(fixes.back().sigma_speed_mps, std::sqrt(2.0) * o.velocity.horizontal_sigma_mps(), 1e-12);
  EXPECT_NEAR(fixes.back().sigma_speed_mps, rms, 0.15 * rms);
  // The vertical velocity has its own error too.
  EXPECT_NE(fixes[10].vel_up_mps, 0.0);
}

TEST(ReceiverVelocity, WhileMovingTheErrorIsAroundTheTruthsVelocity) {
  const ReceiverOptions o;
  const auto east_at_5 = [](int k) {
    sources::Truth t{};
    t.position_m = {5.0 * k, 0.0, 0.0};
    t.velocity_mps = {5.0, 0.0, 0.0};
    return t;
  };
  double sum = 0.0;
  int n = 0;
  for (const nmea::Fix& f : run(o, 2000, east_at_5)) {
    sum += f.speed_mps - 5.0;
    ++n;
    ASSERT_TRUE(f.course_deg_true.has_value());
    EXPECT_NEAR(*f.course_deg_true, 90.0, 3.0);
  }
  EXPECT_NEAR(sum / n, 0.0, 0.005);
}

TEST(ReceiverVelocity, AStaticClampReportsZeroBelowItsThreshold) {
  ReceiverOptions o;
  o.velocity.static_clamp_mps = 0.1;
  int zeros = 0;
  const std::vector<nmea::Fix> fixes = run(o, 1000, still);
  for (const nmea::Fix& f : fixes) {
    EXPECT_TRUE(f.speed_mps == 0.0 || f.speed_mps >= 0.1) << f.speed_mps;
    if (f.speed_mps == 0.0) {
      EXPECT_EQ(f.vel_up_mps, 0.0);
      ++zeros;
    }
  }
  EXPECT_GT(zeros, 900);  // P(speed < 0.1) for sigma 0.036: 98%
}

TEST(ReceiverVelocity, TheCourseAtRestIsEmptyHeldOrMeasuredAsTheChipsetLeavesIt) {
  // Five seconds north at 2 m/s, then still.
  const auto north_then_still = [](int k) {
    sources::Truth t{};
    if (k < 5) t.velocity_mps = {0.0, 2.0, 0.0};
    return t;
  };
  ReceiverOptions o;
  for (const CourseAtRest mode : {CourseAtRest::empty, CourseAtRest::held, CourseAtRest::measured}) {
    o.course_at_rest = mode;
    const std::vector<nmea::Fix> fixes = run(o, 60, north_then_still);
    ASSERT_TRUE(fixes[3].course_deg_true.has_value());
    const double moving = *fixes[3].course_deg_true;
    EXPECT_LT(std::min(moving, 360.0 - moving), 3.0);
    int courses = 0, north = 0;
    for (std::size_t k = 10; k < fixes.size(); ++k) {
      if (!fixes[k].course_deg_true) continue;
      ++courses;
      const double c = *fixes[k].course_deg_true;
      if (std::min(c, 360.0 - c) < 3.0) ++north;
    }
    if (mode == CourseAtRest::empty) {
      EXPECT_EQ(courses, 0);  // u-blox: empty standing still
    }
    if (mode == CourseAtRest::held) {
      EXPECT_EQ(north, 50);  // the last course, as SiRF and SkyTraq
    }
    if (mode == CourseAtRest::measured) {
      EXPECT_EQ(courses, 50);  // the noise's direction: anywhere
      EXPECT_LT(north, 10);
    }
  }
  EXPECT_THROW((void)parse_course_at_rest("sideways"), std::invalid_argument);
  EXPECT_EQ(parse_course_at_rest("held"), CourseAtRest::held);
}

TEST(ReceiverVelocity, StaticHoldReportsNoMotionAndWithoutNoiseTheVelocityIsTheTruths) {
  ReceiverOptions held;
  held.hold.radius_m = 5.0;  // wider than the wander: held from the second epoch on
  const std::vector<nmea::Fix> fixes = run(held, 100, still);
  for (std::size_t k = 1; k < fixes.size(); ++k) EXPECT_EQ(fixes[k].speed_mps, 0.0) << k;

  ReceiverOptions exact;
  exact.velocity.white_sigma_mps = exact.velocity.wander_sigma_mps = 0.0;
  for (const nmea::Fix& f : run(exact, 50, still)) {
    EXPECT_EQ(f.speed_mps, 0.0);
    EXPECT_EQ(f.vel_up_mps, 0.0);
    EXPECT_DOUBLE_EQ(f.sigma_speed_mps, 0.05);  // the autonomous floor
  }
}

}  // namespace receiver_velocity_test
}  // namespace
}  // namespace gpsemu
