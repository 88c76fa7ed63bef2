// The satellite messages byte for byte from a fixed sky (each field hand-checked against u-blox's
// interface descriptions, M8 protocol 18 and F9 HPG 1.32): NAV-SVINFO's u-blox 8 numbering and
// channel/flags/quality, NAV-SIG's one entry per signal (two bands on the F9P, one on the M9N),
// NAV-SAT's gnssId/svId from the satellites' system and sv_id, GLONASS frequency channels.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/nav_sat.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace nav_sat_test {

using namespace std::chrono;
using nmea::GnssSystem;
using test::hex;
using test::unhex;

/// 2026-11-24 12:34:56.2 UTC (iTOW 218114200 = 0x0D002898), a 3-D GPS fix; GPS 5 used, GPS 13
/// tracked, SBAS 120 (NMEA 33, no sv_id: read from the NMEA id) in view but not tracked.
nmea::Fix sky_fix() {
  nmea::Fix f;
  f.time_utc = sys_days{year{2026} / November / 24} + hours{12} + minutes{34} + seconds{56} + milliseconds{200};
  f.quality = nmea::FixQuality::gps;
  f.dimension = nmea::FixDimension::three_d;
  f.satellites_in_view = 3;
  f.satellites[0] = {5, 45, 120, 42, true, GnssSystem::gps, 5};
  f.satellites[1] = {13, 10, 300, 30, false, GnssSystem::gps, 13};
  f.satellites[2] = {33, 30, 200, std::nullopt, false};
  return f;
}

TEST(UbxNavSat, SvinfoIsByteExact) {
  const std::string expected = unhex(
      "9828000d 03 04 0000"                // iTOW, numCh 3, globalFlags chipGen 4 (u-blox 8), reserved
      "00 05 0d 07 2a 2d 7800 00000000"    // chn 0, svid 5, svUsed|orbitAvail|orbitEph, quality 7, 42 dBHz, 45 deg, 120 deg
      "01 0d 04 04 1e 0a 2c01 00000000"    // chn 1, svid 13, orbitAvail, code locked, 30 dBHz, 10 deg, 300 deg
      "ff 78 00 01 00 1e c800 00000000");  // no channel, SBAS 120, searching, 30 deg, 200 deg
  EXPECT_EQ(hex(nav_svinfo(sky_fix())), hex(expected));
}

TEST(UbxNavSat, SigListsTwoBandsOnTheF9pAndOneOnTheM9n) {
  const std::string f9p = unhex(
      "9828000d 00 04 0000"                           // iTOW, version 0, numSigs 4 (SBAS 120 not tracked)
      "00 05 00 00 0000 2a 07 00 08 2900 00000000"    // GPS 5 L1C/A: 42 dBHz, quality 7, dual-frequency iono, healthy|prUsed|doUsed
      "00 05 03 00 0000 26 07 00 08 2900 00000000"    // GPS 5 L2 CL: 4 dB weaker
      "00 0d 00 00 0000 1e 04 00 00 0100 00000000"    // GPS 13 L1C/A: code locked, not used
      "00 0d 03 00 0000 1a 04 00 00 0100 00000000");  // GPS 13 L2 CL
  EXPECT_EQ(hex(nav_sig(sky_fix(), ReceiverModel::ublox_f9p)), hex(f9p));
  const std::string m9n = unhex(
      "9828000d 00 02 0000"
      "00 05 00 00 0000 2a 07 00 01 2900 00000000"    // Klobuchar iono on one band
      "00 0d 00 00 0000 1e 04 00 00 0100 00000000");
  EXPECT_EQ(hex(nav_sig(sky_fix(), ReceiverModel::ublox_m9n)), hex(m9n));
  EXPECT_EQ(signal_count(sky_fix(), ReceiverModel::ublox_f9p), 4);
}

TEST(UbxNavSat, SatUsesEachSatellitesSystemAndNumber) {
  nmea::Fix f = sky_fix();
  f.satellites_in_view = 4;
  f.satellites[3] = {11, 60, 10, 47, true, GnssSystem::galileo, 11};  // NMEA 4.1 id 11 of system 3
  const std::string p = nav_sat(f);
  ASSERT_EQ(p.size(), 8u + 4 * 12);
  EXPECT_EQ(hex(p.substr(0, 8)), "9828000d01040000");  // version 1, numSvs 4
  EXPECT_EQ(hex(p.substr(8 + 36, 12)), "020b2f3c0a0000001f090000");  // Galileo E11: 47 dBHz, 60 deg, 10 deg, used
  EXPECT_EQ(get_u1(p, 32), 1);    // SBAS from the NMEA id 33
  EXPECT_EQ(get_u1(p, 33), 120);
}

TEST(UbxNavSat, GlonassSignalsCarryTheirFrequencyChannel) {
  nmea::Fix f = sky_fix();
  f.satellites_in_view = 1;
  f.satellites[0] = {66, 40, 90, 44, true, GnssSystem::glonass, 2};  // slot 2: channel -4
  const std::string p = nav_sig(f, ReceiverModel::ublox_f9p);
  ASSERT_EQ(p.size(), 8u + 2 * 16);
  EXPECT_EQ(get_u1(p, 8 + 3), 3);       // freqId = channel + 7
  EXPECT_EQ(get_u1(p, 24 + 2), 2);      // L2 OF
  EXPECT_EQ(glonass_frequency_channel(1), 1);
  EXPECT_EQ(glonass_frequency_channel(10), -7);
  EXPECT_EQ(glonass_frequency_channel(25), 0);
}

TEST(UbxNavSat, SvinfoNumbersEverySystemAsAUblox8) {
  EXPECT_EQ(svinfo_svid({0, 32}), 32);
  EXPECT_EQ(svinfo_svid({1, 158}), 158);
  EXPECT_EQ(svinfo_svid({2, 5}), 215);   // Galileo E5
  EXPECT_EQ(svinfo_svid({3, 3}), 161);   // BeiDou B3
  EXPECT_EQ(svinfo_svid({3, 10}), 37);   // BeiDou B10
  EXPECT_EQ(svinfo_svid({5, 1}), 193);   // QZSS J1
  EXPECT_EQ(svinfo_svid({6, 24}), 88);   // GLONASS R24
  EXPECT_EQ(svinfo_svid({3, 63}), 255);  // beyond the u-blox 8 range
}

TEST(UbxNavSat, NoFixMarksNoSatelliteUsed) {
  nmea::Fix f = sky_fix();
  f.quality = nmea::FixQuality::none;
  EXPECT_EQ(get_u1(nav_svinfo(f), 8 + 2) & 0x01, 0);
  EXPECT_EQ(get_u2(nav_sig(f, ReceiverModel::ublox_f9p), 8 + 10) & 0x08, 0);
}

}  // namespace nav_sat_test
}  // namespace
}  // namespace gpsemu::ubx
