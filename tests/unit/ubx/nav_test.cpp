// NAV messages from a fixed fix, byte for byte (golden frames; decoded independently with
// gpsd's gpsdecode when they were made: TPV mode 3 at 47.3977419 N 8.5455938 E, altHAE 535.5,
// altMSL 488, eph 1.0, epv 1.2, speed 5, track 45, eps 0.30; SKY with the three satellites),
// then the fields that follow the receiver state: no fix, 2-D, DGPS and RTK flags, GPS time, the
// time validity flags of a cold start, the accuracy floors, NAV-CLOCK and NAV-HPPOSLLH byte for
// byte (hand-checked), the fix's own TDOP and GDOP.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include "emulator/ubx/bytes.hpp"
#include "emulator/model/accuracy.hpp"
#include "emulator/ubx/nav.hpp"
#include "emulator/ubx/messages.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace nav_test {

using namespace std::chrono;
using test::hex;

nmea::Fix fixed_fix() {
  nmea::Fix f;
  f.time_utc = sys_days{year{2026} / November / 24} + hours{12} + minutes{34} + seconds{56} + milliseconds{200};
  f.quality = nmea::FixQuality::gps;
  f.sigma_speed_mps = 0.3;
  f.dimension = nmea::FixDimension::three_d;
  f.lat_deg = 47.3977419;
  f.lon_deg = 8.5455938;
  f.alt_msl_m = 488.0;
  f.geoid_sep_m = 47.5;
  f.speed_mps = 5.0;
  f.course_deg_true = 45.0;
  f.satellites_used = 12;
  f.hdop = 0.9;
  f.vdop = 1.35;
  f.pdop = 1.62;
  f.sigma_lat_m = 0.6;
  f.sigma_lon_m = 0.8;
  f.sigma_alt_m = 1.2;
  f.range_rms_m = 1.0;
  f.satellites_in_view = 3;
  f.satellites[0] = {5, 45, 120, 42, true};
  f.satellites[1] = {13, 10, 300, 30, false};
  f.satellites[2] = {33, 30, 200, std::nullopt, false};  // SBAS PRN 120
  return f;
}

NavExtras fixed_extras() {
  NavExtras x;
  x.since_start = milliseconds{60000};
  x.time_to_first_fix = milliseconds{28000};
  return x;
}

struct Golden {
  MessageId id;
  std::size_t payload_bytes;
  const char* frame_hex;
};

const Golden goldens[] = {
    {msg::nav_pvt, 92,
     "b56201075c009828000dea070b180c2238071400000000c2eb0b0301e00c42f417054b52401ccc2b080040720700e8030000b004"
     "0000d00d0000d00d0000000000008813000020aa44002c010000433d0500a2000000000000000000000000000000c7a0"},
    {msg::nav_posllh, 28, "b56201021c009828000d42f417054b52401ccc2b080040720700e8030000b00400008e92"},
    {msg::nav_velned, 36, "b562011224009828000d620100006201000000000000f4010000f401000020aa44001e000000433d0500659a"},
    {msg::nav_status, 16, "b562010310009828000d030d0000606d000060ea000008da"},
    {msg::nav_sol, 52,
     "b562010634009828000d000000008e09030dda127f19d0c9d4038c37d91b9c000000cafeffff37010000ef0000001e000000a2"
     "00000c00000000af28"},
    {msg::nav_dop, 18, "b562010412009828000dbd00a200610087005a00400040000579"},
    {msg::nav_timeutc, 20, "b562012114009828000d1400000000c2eb0bea070b180c223837801b"},
    {msg::nav_timegps, 16, "b562012010009828000d000000008e09120714000000c2a3"},
    {msg::nav_sat, 44,
     "b56201352c009828000d0103000000052a2d780000001f090000000d1e0a2c010000140000000178001ec80000001100000015"
     "de"},
    {msg::nav_cov, 64,
     "b562013640009828000d000101000000000000000000ec51b83e00000000000000000ad7233f00000000ec51b83fec51b83d00"
     "00000000000000ec51b83d00000000ec51b83d868d"},
    {msg::nav_posecef, 20, "b562010114009828000dda127f19d0c9d4038c37d91b9c0000002a35"},  // NAV-SOL's ECEF fields
    {msg::nav_velecef, 20, "b562011114009828000dcafeffff37010000ef0000001e000000fe02"},
    {msg::nav_eoe, 4, "b562016104009828000d33ac"},
};

TEST(UbxNav, EachMessageOfTheFixedFixIsByteExact) {
  for (const Golden& g : goldens) {
    const auto payload = solution_payload(g.id, fixed_fix(), fixed_extras());
    ASSERT_TRUE(payload.has_value());
    EXPECT_EQ(payload->size(), g.payload_bytes) << hex(std::string{char(g.id.msg_class), char(g.id.msg_id)});
    EXPECT_EQ(hex(frame_bytes(g.id, *payload)), g.frame_hex)
        << "message " << hex(std::string{char(g.id.msg_class), char(g.id.msg_id)});
  }
}

TEST(UbxNav, PvtFieldsAtTheirOffsets) {
  const std::string p = nav_pvt(fixed_fix(), fixed_extras());
  EXPECT_EQ(get_u4(p, 0), 218114200u);  // iTOW: Tuesday 12:34:56.2 UTC + 18 s
  EXPECT_EQ(get_u2(p, 4), 2026);
  EXPECT_EQ(get_u1(p, 10), 56);
  EXPECT_EQ(get_i4(p, 16), 200'000'000);     // nano
  EXPECT_EQ(get_u1(p, 20), 3);               // fixType 3-D
  EXPECT_EQ(get_u1(p, 21), 0x01);            // gnssFixOK
  EXPECT_EQ(get_u1(p, 23), 12);              // numSV
  EXPECT_EQ(get_i4(p, 24), 85455938);        // lon 1e-7 deg
  EXPECT_EQ(get_i4(p, 28), 473977419);       // lat
  EXPECT_EQ(get_i4(p, 32), 535500);          // height above ellipsoid (mm)
  EXPECT_EQ(get_i4(p, 36), 488000);          // hMSL (mm)
  EXPECT_EQ(get_u4(p, 40), 1000u);           // hAcc = hypot(0.6, 0.8) m
  EXPECT_EQ(get_u4(p, 44), 1200u);           // vAcc
  EXPECT_EQ(get_i4(p, 48), 3536);            // velN mm/s
  EXPECT_EQ(get_i4(p, 52), 3536);            // velE
  EXPECT_EQ(get_i4(p, 60), 5000);            // gSpeed
  EXPECT_EQ(get_i4(p, 64), 4500000);         // headMot 1e-5 deg
  EXPECT_EQ(get_u4(p, 68), 300u);            // sAcc mm/s
  EXPECT_EQ(get_u2(p, 76), 162);             // pDOP 0.01
  EXPECT_EQ(get_u1(p, 78) & 0x01, 0);        // invalidLlh clear
}

TEST(UbxNav, NoFixIsFixTypeZeroWithInvalidPosition) {
  nmea::Fix f = fixed_fix();
  f.quality = nmea::FixQuality::none;
  const std::string p = nav_pvt(f, fixed_extras());
  EXPECT_EQ(get_u1(p, 20), 0);
  EXPECT_EQ(get_u1(p, 21), 0);
  EXPECT_EQ(get_u1(p, 23), 0);
  EXPECT_EQ(get_i4(p, 28), 0);
  EXPECT_EQ(get_u4(p, 40), no_fix_accuracy_mm);
  EXPECT_EQ(get_u1(p, 78) & 0x01, 1);  // invalidLlh
  EXPECT_EQ(get_u1(nav_status(f, fixed_extras()), 4), 0);
}

TEST(UbxNav, TwoDimensionalFixIsFixTypeTwo) {
  nmea::Fix f = fixed_fix();
  f.dimension = nmea::FixDimension::two_d;
  EXPECT_EQ(get_u1(nav_pvt(f, fixed_extras()), 20), 2);
  EXPECT_EQ(get_u1(nav_sol(f, fixed_extras()), 10), 2);
}

TEST(UbxNav, FixQualitySetsDifferentialAndCarrierFlags) {
  nmea::Fix f = fixed_fix();
  f.quality = nmea::FixQuality::dgps;
  EXPECT_EQ(get_u1(nav_pvt(f, fixed_extras()), 21), 0x03);
  f.quality = nmea::FixQuality::rtk_float;
  EXPECT_EQ(get_u1(nav_pvt(f, fixed_extras()), 21), 0x43);
  EXPECT_EQ(get_u1(nav_status(f, fixed_extras()), 6), 0x03);  // fixStat: diffCorr, carrSolnValid
  f.quality = nmea::FixQuality::rtk_fixed;
  EXPECT_EQ(get_u1(nav_pvt(f, fixed_extras()), 21), 0x83);
  EXPECT_EQ(get_u1(nav_status(f, fixed_extras()), 7), 0x80);
  f.quality = nmea::FixQuality::estimated;
  EXPECT_EQ(get_u1(nav_pvt(f, fixed_extras()), 20), 1);  // dead reckoning only
}

TEST(UbxNav, GpsTimeIsUtcPlusLeapSeconds) {
  const GpsTime start = gps_time(sys_days{year{1980} / January / 6} - seconds{gps_leap_seconds});
  EXPECT_EQ(start.week, 0);
  EXPECT_EQ(start.tow_ms, 0u);
  // Sunday 2026-11-22 00:00:00 UTC is 18 s into GPS week 2446.
  const GpsTime sunday = gps_time(sys_days{year{2026} / November / 22});
  EXPECT_EQ(sunday.week, 2446);
  EXPECT_EQ(sunday.tow_ms, 18000u);
}

TEST(UbxNav, SatellitesFollowTheFixAsGsvDoes) {
  const std::string p = nav_sat(fixed_fix());
  ASSERT_EQ(p.size(), 8u + 3 * 12);
  EXPECT_EQ(get_u1(p, 5), 3);                // numSvs
  EXPECT_EQ(get_u1(p, 8 + 1), 5);            // svId
  EXPECT_EQ(get_u1(p, 8 + 2), 42);           // cno
  EXPECT_NE(get_u4(p, 8 + 8) & 0x08, 0u);    // svUsed
  EXPECT_EQ(get_u4(p, 20 + 8) & 0x08, 0u);   // PRN 13 not used
  EXPECT_EQ(get_u1(p, 32), 1);               // SBAS gnssId
  EXPECT_EQ(get_u1(p, 33), 120);             // PRN 120
}

TEST(UbxNav, WithoutTimeNothingIsValidOrConfirmed) {
  NavExtras x = fixed_extras();
  nmea::Fix f = fixed_fix();
  f.quality = nmea::FixQuality::none;
  x.time = {false, false, false};
  EXPECT_EQ(get_u1(nav_pvt(f, x), 11), 0x00);       // valid: no date, no time, not resolved
  EXPECT_EQ(get_u1(nav_pvt(f, x), 22), 0x20);       // flags2: confirmedAvai only
  EXPECT_EQ(get_u1(nav_timeutc(f, x), 19), 0x00);   // no TOW, WKN, UTC; utcStandard unknown
  EXPECT_EQ(get_u1(nav_timegps(f, x), 11), 0x00);
  EXPECT_EQ(get_u1(nav_status(f, x), 5), 0x00);     // neither WKNSET nor TOWSET
  x.time = {true, false, false};                     // a satellite tracked, no fix yet
  EXPECT_EQ(get_u1(nav_pvt(f, x), 11), 0x03);
  EXPECT_EQ(get_u1(nav_timeutc(f, x), 19), 0x03);
  EXPECT_EQ(get_u1(nav_timegps(f, x), 11), 0x03);
  EXPECT_EQ(get_u1(nav_status(f, x), 5), 0x0C);
  x.time = {true, true, false};  // the first fix: UTC resolved, not yet confirmed
  EXPECT_EQ(get_u1(nav_pvt(fixed_fix(), x), 11), 0x07);
  EXPECT_EQ(get_u1(nav_pvt(fixed_fix(), x), 22), 0x20);
  EXPECT_EQ(get_u1(nav_timeutc(fixed_fix(), x), 19), 0x37);
}

TEST(UbxNav, AccuracyIsTheFixsOwnFlooredOnceByTheModel) {
  // --noise none at the autonomous floor the model applied (0.3 m an axis, 0.45 m vertical):
  // hAcc, vAcc and GST say the same; no second floor here.
  nmea::Fix f = fixed_fix();
  f.sigma_lat_m = f.sigma_lon_m = f.sigma_alt_m = f.sigma_speed_mps = 0.0;
  sky::apply_accuracy_floor(f);
  NavExtras x = fixed_extras();
  const std::string p = nav_pvt(f, x);
  EXPECT_EQ(get_u4(p, 40), 424u);      // hAcc: hypot(0.3, 0.3) m
  EXPECT_EQ(get_u4(p, 44), 450u);      // vAcc 0.45 m
  EXPECT_EQ(get_u4(p, 68), 50u);       // sAcc: the speed floor 0.05 m/s, the fix's
  EXPECT_EQ(get_u4(p, 72), 57294u);    // headAcc: atan(0.05 / 5) = 0.57294 deg
  f.sigma_lat_m = 0.8;                 // what the fix says is written, whatever it is
  f.sigma_lon_m = 0.6;
  EXPECT_EQ(get_u4(nav_pvt(f, x), 40), 1000u);
  f.quality = nmea::FixQuality::rtk_fixed;
  f.sigma_lat_m = f.sigma_lon_m = f.sigma_alt_m = 0.0;
  sky::apply_accuracy_floor(f);
  EXPECT_EQ(get_u4(nav_pvt(f, x), 40), 14u);  // hypot(1 cm, 1 cm)
  EXPECT_GT(get_u4(nav_posecef(f), 16), 0u);   // pAcc
  const std::string cov = nav_cov(f, x);
  EXPECT_GT(get_u4(cov, 16), 0u);  // posCovNN
}

TEST(UbxNav, ClockIsByteExact) {
  NavExtras x = fixed_extras();
  x.clock = {123456, -250, 20, 500};
  // iTOW, clkB 123456 ns, clkD -250 ns/s, tAcc 20 ns, fAcc 500 ps/s
  EXPECT_EQ(hex(nav_clock(fixed_fix(), x)), "9828000d" "40e20100" "06ffffff" "14000000" "f4010000");
}

TEST(UbxNav, TimelsIsByteExact) {
  // iTOW, version 0, reserved, srcOfCurrLs GPS, currLs 18, srcOfLsChange GPS, lsChange 0,
  // timeToLsEvent 0, dateOfLsGpsWn 1929, dateOfLsGpsDn 7, reserved, valid (both)
  EXPECT_EQ(hex(nav_timels(fixed_fix(), fixed_extras())),
            "9828000d" "00000000" "02120200" "00000000" "8907" "0700" "000000" "03");
  NavExtras x = fixed_extras();
  x.time = {true, false, false};
  const std::string unresolved = nav_timels(fixed_fix(), x);
  EXPECT_EQ(get_u1(unresolved, 8), 255);  // source unknown
  EXPECT_EQ(get_u1(unresolved, 23), 0);   // nothing valid
}

TEST(UbxNav, HpposllhCarriesTheHighPrecisionParts) {
  nmea::Fix f = fixed_fix();
  f.lat_deg = 47.397741912;     // 47397741912e-9 deg: 473977419 and 12
  f.lon_deg = -122.123456789;   // -122123456789e-9: -1221234567 and -89
  f.alt_msl_m = 488.1237;       // 4881237e-4 m: 488123 mm and 7
  // version 0, reserved, flags 0 (valid), iTOW, lon, lat, height 535.6237 m, hMSL, lonHp -89,
  // latHp 12, heightHp 7, hMSLHp 7, hAcc 1.0 m and vAcc 1.2 m in 0.1 mm.
  EXPECT_EQ(hex(nav_hpposllh(f)), "00000000" "9828000d" "797035b7" "4b52401c" "472c0800" "bb720700"
                                  "a70c0707" "10270000" "e02e0000");
  f.quality = nmea::FixQuality::none;
  EXPECT_EQ(get_u1(nav_hpposllh(f), 3), 1);  // invalidLlh
}

TEST(UbxNav, DopUsesTheFixsTdopAndGdopWhenItHasThem) {
  nmea::Fix f = fixed_fix();
  f.tdop = 0.8;
  f.gdop = 1.9;
  const std::string p = nav_dop(f);
  EXPECT_EQ(get_u2(p, 4), 190);  // gDOP
  EXPECT_EQ(get_u2(p, 8), 80);   // tDOP
}

// The vertical velocity (up positive in the fix) is NAV-PVT's velD in mm/s and NAV-VELNED's in cm/s,
// down positive; VELNED's speed is 3-D, gSpeed the ground speed; NAV-SOL and NAV-VELECEF carry it
// in the ECEF velocity (its up component at the fix's latitude and longitude).
TEST(UbxNav, VerticalVelocityIsVelDAndInTheEcefVelocity) {
  nmea::Fix f = fixed_fix();
  f.speed_mps = 3.0;
  f.course_deg_true = 0.0;
  f.vel_up_mps = 4.0;  // climbing
  const std::string pvt = nav_pvt(f, fixed_extras());
  EXPECT_EQ(static_cast<std::int32_t>(get_u4(pvt, 48)), 3000);   // velN mm/s
  EXPECT_EQ(static_cast<std::int32_t>(get_u4(pvt, 56)), -4000);  // velD mm/s
  EXPECT_EQ(static_cast<std::int32_t>(get_u4(pvt, 60)), 3000);   // gSpeed mm/s
  const std::string velned = nav_velned(f, fixed_extras());
  EXPECT_EQ(static_cast<std::int32_t>(get_u4(velned, 12)), -400);  // velD cm/s
  EXPECT_EQ(get_u4(velned, 16), 500u);                             // speed (3-D) cm/s
  EXPECT_EQ(get_u4(velned, 20), 300u);                             // gSpeed cm/s
  const double lat = f.lat_deg * std::numbers::pi / 180.0, lon = f.lon_deg * std::numbers::pi / 180.0;
  for (const std::string& ecef : {nav_velecef(f, fixed_extras()), nav_sol(f, fixed_extras()).substr(28, 12)}) {
    const std::size_t at = ecef.size() == 20 ? 4 : 0;
    const double x = static_cast<std::int32_t>(get_u4(ecef, at)), y = static_cast<std::int32_t>(get_u4(ecef, at + 4)),
                 z = static_cast<std::int32_t>(get_u4(ecef, at + 8));
    EXPECT_NEAR(std::cos(lat) * std::cos(lon) * x + std::cos(lat) * std::sin(lon) * y + std::sin(lat) * z, 400.0, 1.0);
    EXPECT_NEAR(std::sqrt(x * x + y * y + z * z), 500.0, 1.0);
  }
}

}  // namespace nav_test
}  // namespace
}  // namespace gpsemu::ubx
