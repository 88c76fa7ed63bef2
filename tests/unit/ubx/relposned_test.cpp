// NAV-RELPOSNED version 1: 64 bytes at the offsets ArduPilot and PX4 read, centimetres with the
// 0.1 mm parts (signed alike), the flags of a valid fixed moving-base solution, and the zeros a
// rover writes without its base.
#include <gtest/gtest.h>

#include "emulator/ubx/relposned.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::ubx {
namespace {
namespace relposned_test {

nmea::Fix fixed_fix() {
  nmea::Fix fix;
  fix.quality = nmea::FixQuality::rtk_fixed;
  fix.dimension = nmea::FixDimension::three_d;
  fix.time_utc = nmea::UtcTime{std::chrono::sys_days{std::chrono::year{2024} / 5 / 1}} + std::chrono::hours{12};
  return fix;
}

TEST(RelPosNed, ValidFixedBaselineAtTheF9pOffsets) {
  RelPosNed rel;
  rel.north_m = 1.23456;
  rel.east_m = -0.98771;
  rel.down_m = 0.0012;
  rel.length_m = 1.5811;
  rel.heading_deg = 321.33;
  rel.acc_north_m = rel.acc_east_m = rel.acc_down_m = rel.acc_length_m = 0.01;
  rel.acc_heading_deg = 0.45;
  rel.diff_soln = rel.rel_pos_valid = rel.is_moving = rel.heading_valid = true;
  rel.carrier = CarrierSolution::fixed;
  const std::string p = nav_relposned(fixed_fix(), rel);
  ASSERT_EQ(p.size(), 64u);
  const RelPosNedFields f = read_relposned(p);
  EXPECT_EQ(f.version, 1);
  EXPECT_EQ(f.itow_ms, (3u * 86400u + 12u * 3600u + 18u) * 1000u);  // Wednesday 12:00 UTC + 18 leap seconds
  EXPECT_EQ(f.n_cm, 123);
  EXPECT_EQ(f.hp_n, 46);  // 1.2346 m = 123 cm + 4.6 mm
  EXPECT_EQ(f.e_cm, -98);
  EXPECT_EQ(f.hp_e, -77);  // -0.98771 m -> -9877 x 0.1 mm: -98 cm and -77
  EXPECT_EQ(f.d_cm, 0);
  EXPECT_EQ(f.hp_d, 12);
  EXPECT_EQ(f.length_cm, 158);
  EXPECT_EQ(f.hp_length, 11);
  EXPECT_EQ(f.heading_1e5deg, 32133000);
  EXPECT_EQ(f.acc_n, 100u);
  EXPECT_EQ(f.acc_heading_1e5deg, 45000u);
  // gnssFixOK, diffSoln, relPosValid, carrSoln 2, isMoving, relPosHeadingValid
  EXPECT_EQ(f.flags, 0x1u | 0x2u | 0x4u | (2u << 3) | 0x20u | 0x100u);
}

TEST(RelPosNed, WithoutTheBaseOnlyFixOkAndMoving) {
  RelPosNed rel;
  rel.is_moving = true;
  rel.north_m = 5.0;  // not valid: not written
  const RelPosNedFields f = read_relposned(nav_relposned(fixed_fix(), rel));
  EXPECT_EQ(f.n_cm, 0);
  EXPECT_EQ(f.acc_n, 0u);
  EXPECT_EQ(f.flags, 0x1u | 0x20u);
  nmea::Fix none;
  EXPECT_EQ(read_relposned(nav_relposned(none, rel)).flags, 0x20u);
}

}  // namespace relposned_test
}  // namespace
}  // namespace gpsemu::ubx
