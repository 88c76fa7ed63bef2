// NearGeodetic against the exact conversion it stands in for (LocalFrame::to_geodetic): noisy
// positions about a truth, at several places, a moving truth, a point past the radius, the
// antimeridian and near a pole.
#include "emulator/model/geo_near.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "emulator/model/geo.hpp"

namespace gpsemu {
namespace {
namespace geo_near_test {

// Far below what any output prints (1e-9 degree is 0.1 mm; u-blox's finest field).
constexpr double kAngleTolDeg = 1e-12;  // 0.1 micrometre
constexpr double kHeightTolM = 1e-7;

void expect_same(const Geodetic& a, const Geodetic& b) {
  EXPECT_NEAR(a.lat_deg, b.lat_deg, kAngleTolDeg);
  EXPECT_NEAR(a.lon_deg, b.lon_deg, kAngleTolDeg);
  EXPECT_NEAR(a.alt_m, b.alt_m, kHeightTolM);
}

void check_noise_about(const Geodetic& origin, const Enu& truth, double sigma_m) {
  const LocalFrame frame(origin);
  NearGeodetic near;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, sigma_m);
  for (int i = 0; i < 2000; ++i) {
    const Enu p{truth.east_m + noise(rng), truth.north_m + noise(rng), truth.up_m + noise(rng)};
    SCOPED_TRACE(i);
    expect_same(near.to_geodetic(frame, p), frame.to_geodetic(p));
  }
}

TEST(NearGeodetic, NoisyPositionsAboutAStationaryTruthConvertAsTheExactConversion) {
  check_noise_about({39.5, -119.8, 1400.0}, {0.0, 0.0, 0.0}, 2.0);
  check_noise_about({-33.9, 151.2, 30.0}, {120.0, -45.0, 3.0}, 3.0);
  check_noise_about({60.2, 24.9, 0.0}, {0.0, 0.0, 0.0}, 4.0);  // some past the radius too
}

TEST(NearGeodetic, AMovingTruthConvertsAsTheExactConversion) {
  const LocalFrame frame({35.7, 139.7, 40.0});
  NearGeodetic near;
  for (int i = 0; i < 5000; ++i) {
    const Enu p{1.3 * i, -0.7 * i, 0.01 * i};
    expect_same(near.to_geodetic(frame, p), frame.to_geodetic(p));
  }
}

TEST(NearGeodetic, AcrossTheAntimeridianLongitudeStaysWrapped) {
  const LocalFrame frame({-17.0, 179.99999, 0.0});
  NearGeodetic near;
  for (int i = 0; i < 40; ++i) {
    const Enu p{0.5 * i - 1.0, 0.0, 0.0};
    const Geodetic got = near.to_geodetic(frame, p);
    const Geodetic want = frame.to_geodetic(p);
    EXPECT_GE(got.lon_deg, -180.0);
    EXPECT_LT(got.lon_deg, 180.0);
    expect_same(got, want);
  }
}

TEST(NearGeodetic, NearAPoleConvertsExactly) {
  const LocalFrame frame({89.9999, 10.0, 0.0});
  NearGeodetic near;
  for (int i = 0; i < 20; ++i) {
    const Enu p{0.3 * i, 0.2 * i, 0.0};
    const Geodetic got = near.to_geodetic(frame, p);
    const Geodetic want = frame.to_geodetic(p);
    EXPECT_EQ(got.lat_deg, want.lat_deg);
    EXPECT_EQ(got.lon_deg, want.lon_deg);
    EXPECT_EQ(got.alt_m, want.alt_m);
  }
}

}  // namespace geo_near_test
}  // namespace
}  // namespace gpsemu
