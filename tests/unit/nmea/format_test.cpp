// GGA and RMC formatters: checksums of published sentences, exact sentences for fixes and no
// fixes (u-blox manual examples reproduced byte for byte), talker, NMEA 2.3/4.1 field counts,
// mode letters, knots, course, and the 82-character limit.
#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"
#include "tests/support/nmea_values.hpp"

namespace gpsemu::nmea {
namespace {
namespace format_test {

using namespace std::chrono;
using test::utc;
using test::dm;
using test::mps_per_knot;

// The comma-separated parts of "$...*hh\r\n" (address first), without parsing it as NMEA.
std::vector<std::string> parts(const std::string& sentence) {
  std::vector<std::string> out(1);
  for (char c : sentence.substr(1, sentence.find('*') - 1)) {
    if (c == ',') out.emplace_back();
    else out.back() += c;
  }
  return out;
}

FormatOptions options(std::string talker, int minute_decimals, int time_decimals, NmeaVersion version) {
  return FormatOptions{std::move(talker), minute_decimals, time_decimals, version};
}

TEST(NmeaChecksum, PublishedSentencesRecompute) {
  const std::vector<std::string> published = {
      "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47",
      "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A",
      "$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B",  // u-blox
      "$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A*57",    // u-blox
      "$GPGGA,,,,,,0,00,99.99,,,,,,*48",                                            // u-blox no fix
  };
  for (const std::string& s : published) {
    const std::string body = s.substr(1, s.size() - 4);
    EXPECT_EQ(checksum(body), std::stoi(s.substr(s.size() - 2), nullptr, 16)) << s;
    EXPECT_EQ(frame(body), s + "\r\n");
  }
}

Fix ublox_fix() {
  Fix fix;
  fix.time_utc = utc(2002, 12, 9, 9, 27, 25);
  fix.quality = FixQuality::gps;
  fix.lat_deg = dm(47, 17.11399);
  fix.lon_deg = dm(8, 33.91590);
  fix.satellites_used = 8;
  fix.hdop = 1.01;
  fix.alt_msl_m = 499.6;
  fix.geoid_sep_m = 48.0;
  return fix;
}

TEST(NmeaFormat, GgaReproducesUbloxManualExample) {
  EXPECT_EQ(format_gga(ublox_fix(), options("GP", 5, 2, NmeaVersion::v4_1)),
            "$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n");
}

TEST(NmeaFormat, RmcReproducesUbloxManualExampleIn23And41) {
  Fix fix = ublox_fix();
  fix.time_utc = utc(2002, 12, 9, 8, 35, 59);
  fix.lat_deg = dm(47, 17.11437);
  fix.lon_deg = dm(8, 33.91522);
  fix.speed_mps = 0.004 * mps_per_knot;
  fix.course_deg_true = 77.52;
  EXPECT_EQ(format_rmc(fix, options("GP", 5, 2, NmeaVersion::v2_3)),
            "$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A*57\r\n");
  EXPECT_EQ(format_rmc(fix, options("GP", 5, 2, NmeaVersion::v4_1)),
            "$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A,V*2D\r\n");
}

TEST(NmeaFormat, NoFixLeavesEverythingButTimeAndDateEmpty) {
  Fix fix = ublox_fix();  // position and speed present but must not be printed
  fix.quality = FixQuality::none;
  fix.speed_mps = 3.0;
  fix.course_deg_true = 10.0;
  fix.time_utc = utc(2023, 12, 31, 23, 59, 59, 999);
  EXPECT_EQ(format_gga(fix, options("GP", 5, 2, NmeaVersion::v4_1)),
            "$GPGGA,235959.99,,,,,0,00,99.99,,,,,,*67\r\n");
  EXPECT_EQ(format_rmc(fix, options("GP", 5, 2, NmeaVersion::v4_1)),
            "$GPRMC,235959.99,V,,,,,,,311223,,,N,V*06\r\n");
  EXPECT_EQ(format_rmc(fix, options("GP", 5, 2, NmeaVersion::v2_3)),
            "$GPRMC,235959.99,V,,,,,,,311223,,,N*7C\r\n");
  fix.time_utc = utc(2024, 1, 1, 0, 0, 0);
  EXPECT_EQ(format_gga(fix, options("GN", 5, 2, NmeaVersion::v4_1)),
            "$GNGGA,000000.00,,,,,0,00,99.99,,,,,,*78\r\n");
  EXPECT_EQ(format_rmc(fix, options("GN", 5, 2, NmeaVersion::v4_1)),
            "$GNRMC,000000.00,V,,,,,,,010124,,,N,V*1F\r\n");
}

TEST(NmeaFormat, SouthEastRtkWithTalkerGnAndMilliseconds) {
  Fix fix;
  fix.time_utc = utc(2024, 2, 29, 1, 2, 3, 456);
  fix.quality = FixQuality::rtk_fixed;
  fix.lat_deg = -dm(33, 51.40704);
  fix.lon_deg = dm(151, 12.91782);
  fix.satellites_used = 12;
  fix.hdop = 0.7;
  fix.alt_msl_m = 4.25;
  fix.geoid_sep_m = 22.8;
  fix.speed_mps = 0.0;
  const FormatOptions o = options("GN", 5, 3, NmeaVersion::v4_1);
  EXPECT_EQ(format_gga(fix, o), "$GNGGA,010203.456,3351.40704,S,15112.91782,E,4,12,0.70,4.3,M,22.8,M,,*66\r\n");
  EXPECT_EQ(format_rmc(fix, o), "$GNRMC,010203.456,A,3351.40704,S,15112.91782,E,0.000,,290224,,,R,V*22\r\n");
}

TEST(NmeaFormat, NorthWestDgpsWithFourDecimalsAndWholeSeconds) {
  Fix fix;
  fix.time_utc = utc(2024, 1, 1, 0, 0, 0);
  fix.quality = FixQuality::dgps;
  fix.lat_deg = 37.7749;
  fix.lon_deg = -122.4194;
  fix.satellites_used = 7;
  fix.hdop = 1.2;
  fix.alt_msl_m = -3.04;
  fix.geoid_sep_m = -32.1;
  fix.speed_mps = 10.0;
  fix.course_deg_true = 359.996;
  const FormatOptions o = options("GP", 4, 0, NmeaVersion::v2_3);
  EXPECT_EQ(format_gga(fix, o), "$GPGGA,000000,3746.4940,N,12225.1640,W,2,07,1.20,-3.0,M,-32.1,M,,*6E\r\n");
  EXPECT_EQ(format_rmc(fix, o), "$GPRMC,000000,A,3746.4940,N,12225.1640,W,19.438,0.00,010124,,,D*6C\r\n");
}

TEST(NmeaFormat, FieldCountsPerSentenceAndVersion) {
  Fix fix = ublox_fix();
  for (const FixQuality q : {FixQuality::none, FixQuality::gps}) {
    fix.quality = q;
    EXPECT_EQ(parts(format_gga(fix, options("GP", 5, 2, NmeaVersion::v2_3))).size(), 15u);  // address + 14
    EXPECT_EQ(parts(format_rmc(fix, options("GP", 5, 2, NmeaVersion::v2_3))).size(), 13u);  // + mode
    EXPECT_EQ(parts(format_rmc(fix, options("GP", 5, 2, NmeaVersion::v4_1))).size(), 14u);  // + nav status
  }
}

TEST(NmeaFormat, ModeLetterAndQualityDigitPerFixQuality) {
  struct Case {
    FixQuality quality;
    std::string gga_quality;
    std::string rmc_status;
    std::string rmc_mode;
  };
  const std::vector<Case> cases = {
      {FixQuality::none, "0", "V", "N"},      {FixQuality::gps, "1", "A", "A"},
      {FixQuality::dgps, "2", "A", "D"},      {FixQuality::pps, "3", "A", "P"},
      {FixQuality::rtk_fixed, "4", "A", "R"}, {FixQuality::rtk_float, "5", "A", "F"},
      {FixQuality::estimated, "6", "A", "E"},
  };
  Fix fix = ublox_fix();
  for (const Case& c : cases) {
    fix.quality = c.quality;
    const auto gga = parts(format_gga(fix, FormatOptions{}));
    const auto rmc = parts(format_rmc(fix, options("GP", 5, 2, NmeaVersion::v2_3)));
    EXPECT_EQ(gga[6], c.gga_quality);
    EXPECT_EQ(rmc[2], c.rmc_status);
    EXPECT_EQ(rmc[12], c.rmc_mode);
    EXPECT_EQ(std::string(1, mode_indicator(c.quality)), c.rmc_mode);
  }
}

TEST(NmeaFormat, SpeedInKnotsWithThreeDecimals) {
  const std::vector<std::pair<double, std::string>> cases = {
      {0.0, "0.000"},   {mps_per_knot, "1.000"}, {1.0, "1.944"},  // 1 m/s = 1.943844 kn
      {10.0, "19.438"}, {100.0, "194.384"},     {-1.0, "1.944"},  // magnitude
      {0.0001, "0.000"},
  };
  Fix fix = ublox_fix();
  for (const auto& [mps, knots] : cases) {
    fix.speed_mps = mps;
    EXPECT_EQ(parts(format_rmc(fix, FormatOptions{}))[7], knots) << mps;
  }
}

TEST(NmeaFormat, CourseTwoDecimalsInZeroTo360OrEmpty) {
  const std::vector<std::pair<std::optional<double>, std::string>> cases = {
      {std::nullopt, ""},   {84.4, "84.40"},    {0.0, "0.00"},     {359.994, "359.99"},
      {359.996, "0.00"},    {-10.0, "350.00"},  {720.5, "0.50"},
  };
  Fix fix = ublox_fix();
  for (const auto& [course, text] : cases) {
    fix.course_deg_true = course;
    EXPECT_EQ(parts(format_rmc(fix, FormatOptions{}))[8], text) << text;
  }
}

TEST(NmeaFormat, SatellitesTwoDigitsAndHdopCapped) {
  Fix fix = ublox_fix();
  fix.satellites_used = 123;
  fix.hdop = 250.0;
  const auto gga = parts(format_gga(fix, FormatOptions{}));
  EXPECT_EQ(gga[7], "99");
  EXPECT_EQ(gga[8], "99.99");
}

// The widest realistic values: 23:59:59.99, 89°59.99999' S, 179°59.99999' W, RTK float, 32
// satellites, HDOP 99.99, 50 000 m (u-blox airborne limit), geoid -106.9 m (the deepest geoid low
// is about -106 m), 500 m/s (u-blox velocity limit), course 359.99, talker GN, NMEA 4.1.
// With u-blox's 5 decimals and 2 time decimals both sentences fit the standard's 82 characters
// (CR LF included); GGA still fits with 6 decimals, and 7 decimals make it 84 characters, which is
// why the parser accepts up to 120 (max_parse_chars).
TEST(NmeaFormat, WidestRealisticSentencesFit82Characters) {
  Fix fix;
  fix.time_utc = utc(2099, 12, 31, 23, 59, 59, 999);
  fix.quality = FixQuality::rtk_float;
  fix.lat_deg = -dm(89, 59.99999);
  fix.lon_deg = -dm(179, 59.99999);
  fix.satellites_used = 32;
  fix.hdop = 99.99;
  fix.alt_msl_m = 50000.0;
  fix.geoid_sep_m = -106.9;
  fix.speed_mps = 500.0;
  fix.course_deg_true = 359.99;
  const FormatOptions ublox = options("GN", 5, 2, NmeaVersion::v4_1);
  EXPECT_EQ(format_gga(fix, ublox).size(), 80u);
  EXPECT_EQ(format_rmc(fix, ublox).size(), 78u);
  EXPECT_EQ(format_gga(fix, options("GN", 6, 2, NmeaVersion::v4_1)).size(), 82u);
  EXPECT_EQ(format_gga(fix, options("GN", 7, 2, NmeaVersion::v4_1)).size(), 84u);
  EXPECT_EQ(format_gga(fix, options("GN", 5, 3, NmeaVersion::v4_1)).size(), 81u);
}

TEST(NmeaFormat, UnusableValuesGiveEmptyFieldsNotGarbage) {
  Fix fix = ublox_fix();
  fix.lat_deg = std::numeric_limits<double>::quiet_NaN();
  fix.alt_msl_m = 1e300;
  const auto gga = parts(format_gga(fix, FormatOptions{}));
  EXPECT_EQ(gga[2], "");
  EXPECT_EQ(gga[3], "");
  EXPECT_EQ(gga[4], "00833.91590");
  EXPECT_EQ(gga[9], "");
  EXPECT_EQ(gga[10], "");
}

TEST(NmeaFormat, GgaAltitudeWithTheConfiguredDecimals) {
  // Issue 27: a receiver's centimetre vertical noise vanished in 0.1 m steps; --alt-decimals.
  Fix fix = ublox_fix();
  fix.alt_msl_m = 499.61237;
  FormatOptions f;
  EXPECT_EQ(parts(format_gga(fix, f))[9], "499.6");  // the default: u-blox's one decimal
  f.alt_decimals = 3;
  EXPECT_EQ(parts(format_gga(fix, f))[9], "499.612");
  EXPECT_EQ(parts(format_gga(fix, f))[11], parts(format_gga(fix, FormatOptions{}))[11]);  // separation unchanged
  f.alt_decimals = 0;
  EXPECT_EQ(parts(format_gga(fix, f))[9], "500");
  f.alt_decimals = 4;
  fix.alt_msl_m = -999999.12345;  // the widest altitude written still parses back
  const auto gga = parse_sentence(format_gga(fix, f));
  ASSERT_TRUE(gga);
  EXPECT_NEAR(*parse_gga(*gga)->alt_msl_m, -999999.1235, 1e-6);
}

}  // namespace format_test
}  // namespace
}  // namespace gpsemu::nmea
