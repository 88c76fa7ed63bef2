// The places that trigger a fault: circles and polygons parsed from their text, inside or not.
#include "emulator/faults/area.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace gpsemu::faults {
namespace {
namespace area_test {

TEST(Area, CircleContainsWhatIsWithinItsRadius) {
  const Area a = parse_area("circle:47.0,8.0,500");
  EXPECT_TRUE(a.contains({47.0, 8.0, 0.0}));
  EXPECT_TRUE(a.contains({47.004, 8.0, 0.0}));   // 445 m north
  EXPECT_FALSE(a.contains({47.005, 8.0, 0.0}));  // 556 m north
  EXPECT_NEAR(surface_distance_m({47.0, 8.0, 0.0}, {47.0, 8.01, 0.0}), 758.3, 1.0);
  EXPECT_EQ(a.text(), "circle:47,8,500");
}

TEST(Area, PolygonContainsItsInsideOnly) {
  const Area a = parse_area("polygon:47.0,8.0;47.0,8.01;47.01,8.01;47.01,8.0");
  EXPECT_TRUE(a.contains({47.005, 8.005, 0.0}));
  EXPECT_FALSE(a.contains({47.011, 8.005, 0.0}));
  EXPECT_FALSE(a.contains({47.005, 7.999, 0.0}));
  const Area l = parse_area("polygon:0,0;0,2;2,2;2,1;1,1;1,0");  // an L shape
  EXPECT_TRUE(l.contains({0.5, 0.5, 0.0}));
  EXPECT_TRUE(l.contains({1.5, 1.5, 0.0}));
  EXPECT_FALSE(l.contains({1.5, 0.5, 0.0}));
}

TEST(Area, BadTextsAreOneClearMessage) {
  const auto message = [](const char* text) {
    try {
      (void)parse_area(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("square:1,2,3"), "where: expected circle:LAT,LON,RADIUS_M or polygon:LAT,LON;LAT,LON;LAT,LON, got 'square:1,2,3'");
  EXPECT_EQ(message("circle:47,8"), "where: expected circle:LAT,LON,RADIUS_M, got 'circle:47,8'");
  EXPECT_EQ(message("circle:97,8,10"), "where: latitude 97 is outside [-90, 90]");
  EXPECT_EQ(message("circle:47,8,-1"), "where: radius -1 m is outside (0, 2e7]");
  EXPECT_EQ(message("circle:47,x,10"), "where: longitude: 'x' is not a number");
  EXPECT_EQ(message("polygon:1,1;2,2"), "where: a polygon needs at least 3 corners, got 2");
  EXPECT_EQ(message("polygon:1,1;2;3,3"), "where: a polygon corner is LAT,LON, got '2'");
}

}  // namespace area_test
}  // namespace
}  // namespace gpsemu::faults
