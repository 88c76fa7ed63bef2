// Field-level formatting: latitude/longitude rounding and hemispheres, hhmmss.ss times, ddmmyy
// dates and fixed-decimal numbers (nmea/fields.hpp).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "nmea/fields.hpp"
#include "nmea/text_append.hpp"
#include "tests/support/nmea_values.hpp"

namespace gpsemu::nmea {
namespace {
namespace fields_test {

using namespace std::chrono;
using test::utc;
using test::dm;

struct CoordinateCase {
  const char* name;
  double deg;
  int minute_decimals;
  std::string value;
  std::string hemisphere;
};

TEST(NmeaFields, LatitudeRoundsFirstThenSplits) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<CoordinateCase> cases = {
      {"classic 3 decimals", dm(48, 7.038), 3, "4807.038", "N"},
      {"u-blox 5 decimals", dm(47, 17.11399), 5, "4717.11399", "N"},
      {"59.9999994' rounds up to the next degree", dm(47, 59.9999994), 5, "4800.00000", "N"},
      {"59.999996' rounds up at 5 decimals", dm(47, 59.999996), 5, "4800.00000", "N"},
      {"59.999996' kept at 7 decimals", dm(47, 59.999996), 7, "4759.9999960", "N"},
      {"59.99996' at 4 decimals", dm(12, 59.99996), 4, "1300.0000", "N"},
      {"just above half a unit rounds up", dm(12, 30.000051), 4, "1230.0001", "N"},
      {"just below half a unit rounds down", dm(12, 30.000049), 4, "1230.0000", "N"},
      {"equator is N", 0.0, 5, "0000.00000", "N"},
      {"negative zero is N", -0.0, 5, "0000.00000", "N"},
      {"tiny south rounding to zero is N", -1e-12, 5, "0000.00000", "N"},
      {"southern hemisphere", -dm(33, 51.40704), 5, "3351.40704", "S"},
      {"one unit south of the equator", -dm(0, 0.00001), 5, "0000.00001", "S"},
      {"north pole", 90.0, 5, "9000.00000", "N"},
      {"south pole", -90.0, 5, "9000.00000", "S"},
      {"rounds to the pole", 89.99999999, 5, "9000.00000", "N"},
      {"8 decimals", dm(89, 59.99999999), 8, "8959.99999999", "N"},
      {"decimals below 1 clamp to 1", dm(10, 5.26), 0, "1005.3", "N"},
      {"decimals above 8 clamp to 8", dm(10, 5.25), 12, "1005.25000000", "N"},
      {"beyond the pole is empty", 90.5, 5, "", ""},
      {"NaN is empty", nan, 5, "", ""},
  };
  for (const CoordinateCase& c : cases) {
    const fields::CoordinateFields out = fields::format_latitude(c.deg, c.minute_decimals);
    EXPECT_EQ(out.value, c.value) << c.name;
    EXPECT_EQ(out.hemisphere, c.hemisphere) << c.name;
  }
}

TEST(NmeaFields, LongitudeRoundsFirstThenSplits) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<CoordinateCase> cases = {
      {"classic 3 decimals", dm(11, 31.0), 3, "01131.000", "E"},
      {"u-blox 5 decimals", dm(8, 33.91590), 5, "00833.91590", "E"},
      {"prime meridian is E", 0.0, 5, "00000.00000", "E"},
      {"negative zero is E", -0.0, 5, "00000.00000", "E"},
      {"western hemisphere 7 decimals", -dm(122, 25.164), 7, "12225.1640000", "W"},
      {"western hemisphere 4 decimals", -dm(122, 25.16449), 4, "12225.1645", "W"},
      {"179.9999999 (59.999994') rounds up at 4 decimals", 179.9999999, 4, "18000.0000", "E"},
      {"179.9999999 (59.999994') stays at 5 decimals", 179.9999999, 5, "17959.99999", "E"},
      {"179.9999999 (59.999994') kept at 7 decimals", 179.9999999, 7, "17959.9999940", "E"},
      {"179.99999999 rounds up at 5 decimals", 179.99999999, 5, "18000.00000", "E"},
      {"-179.99999999 rounds to 180 W", -179.99999999, 5, "18000.00000", "W"},
      {"+180", 180.0, 5, "18000.00000", "E"},
      {"-180", -180.0, 5, "18000.00000", "W"},
      {"190 wraps to 170 W", 190.0, 5, "17000.00000", "W"},
      {"-190 wraps to 170 E", -190.0, 5, "17000.00000", "E"},
      {"59.9999996' at 6 decimals", dm(7, 59.9999996), 6, "00800.000000", "E"},
      {"infinity is empty", inf, 5, "", ""},
  };
  for (const CoordinateCase& c : cases) {
    const fields::CoordinateFields out = fields::format_longitude(c.deg, c.minute_decimals);
    EXPECT_EQ(out.value, c.value) << c.name;
    EXPECT_EQ(out.hemisphere, c.hemisphere) << c.name;
  }
}

TEST(NmeaFields, TimeOfDayIsTruncatedNeverRounded) {
  struct Case {
    UtcTime time;
    int decimals;
    std::string expected;
  };
  const UtcTime last_ms = utc(2023, 12, 31, 23, 59, 59, 999);
  const std::vector<Case> cases = {
      {utc(1994, 3, 23, 12, 35, 19), 0, "123519"},
      {last_ms, 0, "235959"},
      {last_ms, 1, "235959.9"},
      {last_ms, 2, "235959.99"},
      {last_ms, 3, "235959.999"},
      {utc(2024, 1, 1, 0, 0, 0), 2, "000000.00"},
      {utc(2024, 1, 1, 12, 0, 0, 50), 1, "120000.0"},
      {utc(2024, 1, 1, 12, 0, 0, 50), 2, "120000.05"},
      {utc(2024, 1, 1, 12, 0, 0, 50), 3, "120000.050"},
      {utc(2024, 1, 1, 9, 5, 7, 100), 5, "090507.100"},  // clamped to 3
      {utc(2024, 1, 1, 9, 5, 7, 100), -1, "090507"},     // clamped to 0
      {utc(1969, 12, 31, 23, 0, 1, 500), 1, "230001.5"},  // before the epoch
  };
  for (const Case& c : cases) {
    EXPECT_EQ(fields::format_time_of_day(c.time, c.decimals), c.expected) << c.expected;
  }
}

TEST(NmeaFields, DateIsDdMmYy) {
  struct Case {
    UtcTime time;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {utc(1994, 3, 23, 12, 35, 19), "230394"},
      {utc(2023, 12, 31, 23, 59, 59, 990), "311223"},
      {utc(2024, 1, 1, 0, 0, 0), "010124"},
      {utc(2024, 2, 29, 12, 0, 0), "290224"},
      {utc(2000, 1, 1, 0, 0, 0), "010100"},
      {utc(2102, 7, 4, 0, 0, 0), "040702"},
  };
  for (const Case& c : cases) EXPECT_EQ(fields::format_date_ddmmyy(c.time), c.expected) << c.expected;
}

TEST(NmeaFields, FixedDecimalsNeverNegativeZero) {
  EXPECT_EQ(fields::format_fixed(545.44, 1), "545.4");
  EXPECT_EQ(fields::format_fixed(4.25, 1), "4.3");  // half away from zero
  EXPECT_EQ(fields::format_fixed(-4.25, 1), "-4.3");
  EXPECT_EQ(fields::format_fixed(-0.04, 1), "0.0");
  EXPECT_EQ(fields::format_fixed(-0.0, 2), "0.00");
  EXPECT_EQ(fields::format_fixed(19.43844, 3), "19.438");
  EXPECT_EQ(fields::format_fixed(std::nan(""), 1), "");
  EXPECT_EQ(fields::format_fixed(1e7, 1, 1e6), "");
}

TEST(NmeaText, RoundHalfAwayIsLlround) {
  // The inline rounding of the per-epoch formatters against the libm function it replaces, on
  // the halves, the doubles next to them, and magnitudes where every double is a whole number.
  std::vector<double> values = {0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0.49999999999999994,
                                -0.49999999999999994, 4503599627370495.5, -4503599627370495.5,
                                4503599627370497.0, 9007199254740993.0, 1e15 - 0.5, 4.6e18, -4.6e18};
  for (double v = -1000.0; v <= 1000.0; v += 0.125) {
    values.push_back(v);
    values.push_back(std::nextafter(v, 1e300));
    values.push_back(std::nextafter(v, -1e300));
  }
  for (const double v : values) EXPECT_EQ(text::round_half_away(v), std::llround(v)) << v;
}

TEST(NmeaText, ChecksumOfEveryLengthAndByte) {
  // xor_bytes works eight bytes at a time: every length 0..40 and every byte value in every lane.
  std::string body;
  for (int i = 0; i < 40; ++i) body += static_cast<char>(' ' + (i * 37) % 90);
  for (std::size_t n = 0; n <= body.size(); ++n) {
    unsigned char expected = 0;
    for (std::size_t i = 0; i < n; ++i) expected ^= static_cast<unsigned char>(body[i]);
    EXPECT_EQ(text::xor_bytes(body.data(), body.data() + n), expected) << n;
  }
  for (int byte = 0; byte < 256; ++byte) {
    for (std::size_t lane = 0; lane < 9; ++lane) {
      std::string bytes(9, '\0');
      bytes[lane] = static_cast<char>(byte);
      EXPECT_EQ(text::xor_bytes(bytes.data(), bytes.data() + bytes.size()), byte) << lane;
    }
  }
}

TEST(NmeaText, DigitsArePadded) {
  char out[24];
  EXPECT_EQ(std::string(out, text::put_uint(out, 0)), "0");
  EXPECT_EQ(std::string(out, text::put_uint(out, 7, 2)), "07");
  EXPECT_EQ(std::string(out, text::put_uint(out, 12345, 3)), "12345");
  EXPECT_EQ(std::string(out, text::put_uint(out, 18446744073709551615ULL)), "18446744073709551615");
  EXPECT_EQ(std::string(out, text::put_digits(out, 5, 8)), "00000005");
  EXPECT_EQ(std::string(out, text::put_scaled(out, -1230, 2)), "-12.30");
  EXPECT_EQ(std::string(out, text::put_scaled(out, 5, 3)), "0.005");
  EXPECT_EQ(std::string(out, text::put_scaled(out, 42, 0)), "42");
}

}  // namespace fields_test
}  // namespace
}  // namespace gpsemu::nmea
