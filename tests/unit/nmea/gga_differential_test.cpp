// GGA's differential fields (13: age of the corrections in seconds, 14: reference station ID), as
// a u-blox F9P writes them with RTK ("...,M,1.0,0042*hh"), empty without corrections, and the
// widest values within the buffer; a typical one within 82 characters.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {
namespace gga_differential_test {

using namespace std::chrono;

Fix rtk_fix() {
  Fix fix;
  fix.time_utc = UtcTime{sys_days{year{2026} / November / 26} + hours{10} + minutes{1} + seconds{2}};
  fix.quality = FixQuality::rtk_fixed;
  fix.dimension = FixDimension::three_d;
  fix.lat_deg = 47.5;
  fix.lon_deg = 8.25;
  fix.alt_msl_m = 430.1;
  fix.geoid_sep_m = 47.3;
  fix.satellites_used = 20;
  fix.hdop = 0.6;
  return fix;
}

Fix rtk_fix_with(double age_s, int station) {
  Fix fix = rtk_fix();
  fix.diff_age_s = age_s;
  fix.diff_station_id = station;
  return fix;
}

std::string fields_13_14(const std::string& gga) {
  const std::size_t star = gga.find('*');
  std::size_t comma = gga.rfind(',', star);
  comma = gga.rfind(',', comma - 1);
  return gga.substr(comma + 1, star - comma - 1);
}

TEST(NmeaGgaDifferential, EmptyWithoutCorrections) {
  Fix fix = rtk_fix();
  fix.quality = FixQuality::gps;
  const std::string gga = format_gga(fix, FormatOptions{});
  EXPECT_EQ(fields_13_14(gga), ",");
}

TEST(NmeaGgaDifferential, AgeWithOneDecimalAndFourDigitStation) {
  Fix fix = rtk_fix();
  fix.diff_age_s = 1.04;
  fix.diff_station_id = 42;
  const std::string gga = format_gga(fix, FormatOptions{});
  EXPECT_EQ(fields_13_14(gga), "1.0,0042") << gga;
  EXPECT_NE(gga.find(",4,20,"), std::string::npos) << gga;
  std::string line = gga;
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  EXPECT_TRUE(parse_sentence(line).ok()) << gga;
}

TEST(NmeaGgaDifferential, WidestValuesAreClampedAndFit) {
  Fix fix = rtk_fix();
  fix.quality = FixQuality::rtk_float;
  fix.lat_deg = -(89.0 + 59.99999 / 60.0);
  fix.lon_deg = -(179.0 + 59.99999 / 60.0);
  fix.alt_msl_m = -12345.6;
  fix.geoid_sep_m = -106.9;
  fix.hdop = 99.99;
  fix.diff_age_s = 5000.0;
  fix.diff_station_id = 99999;
  FormatOptions options;
  options.minute_decimals = 8;
  options.time_decimals = 3;
  const std::string gga = format_gga(fix, options);
  EXPECT_EQ(fields_13_14(gga), "999.9,4095") << gga;  // within the formatter's buffer (ASan checks it)
  // A typical RTK GGA at u-blox's resolution (5 decimals of minutes, 2 of seconds) stays within 82
  // characters with its differential fields.
  const std::string typical = format_gga(rtk_fix_with(1.0, 0), FormatOptions{});
  EXPECT_EQ(fields_13_14(typical), "1.0,0000") << typical;
  EXPECT_LE(typical.size(), 82u + 2u) << typical;
}

}  // namespace gga_differential_test
}  // namespace
}  // namespace gpsemu::nmea
