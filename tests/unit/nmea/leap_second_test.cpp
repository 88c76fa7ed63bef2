// A fix inside an inserted leap second (Fix::leap.in_second_60, its time_utc the second before):
// every time field reads 23:59:60 with the fraction kept, the dates (RMC, ZDA) stay the old day,
// and the sentences parse back with second 60.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "nmea/fields.hpp"
#include "nmea/fix.hpp"
#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {
namespace leap_second_test {

using namespace std::chrono;

/// A fix at 2026-12-31 23:59:59.500, inside the leap second when `second_60`.
Fix leap_fix(bool second_60) {
  Fix fix;
  fix.time_utc = UtcTime{sys_days{year{2026} / December / 31}} + hours{23} + minutes{59} + seconds{59} + milliseconds{500};
  fix.quality = FixQuality::gps;
  fix.dimension = FixDimension::three_d;
  fix.lat_deg = 47.5;
  fix.lon_deg = 8.5;
  fix.satellites_used = 8;
  fix.hdop = 0.9;
  fix.sigma_lat_m = fix.sigma_lon_m = fix.sigma_alt_m = 1.0;
  fix.leap.in_second_60 = second_60;
  return fix;
}

/// Field `i` (0: the address) of `sentence`.
std::string field(const std::string& sentence, int i) {
  std::size_t begin = 0;
  for (int k = 0; k < i; ++k) begin = sentence.find(',', begin) + 1;
  const std::size_t end = sentence.find_first_of(",*", begin);
  return sentence.substr(begin, end - begin);
}

TEST(LeapSecondFields, TheTimeOfDayReadsSecond60WithItsFraction) {
  const UtcTime t = leap_fix(true).time_utc;
  EXPECT_EQ(fields::format_time_of_day(t, 2), "235959.50");
  EXPECT_EQ(fields::format_time_of_day(t, 2, true), "235960.50");
  EXPECT_EQ(fields::format_time_of_day(t, 0, true), "235960");
  EXPECT_EQ(fields::format_time_of_day(t, 3, true), "235960.500");
}

TEST(LeapSecondSentences, GgaRmcGllZdaGstShow235960AndTheDatesTheOldDay) {
  FormatOptions options;
  const Fix fix = leap_fix(true);
  EXPECT_EQ(field(format_gga(fix, options), 1), "235960.50");
  const std::string rmc = format_rmc(fix, options);
  EXPECT_EQ(field(rmc, 1), "235960.50");
  EXPECT_EQ(field(rmc, 9), "311226") << "the date stays the old day during second 60: " << rmc;
  EXPECT_EQ(field(format_gll(fix, options), 5), "235960.50");
  const std::string zda = format_zda(fix, options);
  EXPECT_EQ(field(zda, 1), "235960.50");
  EXPECT_EQ(field(zda, 2) + field(zda, 3) + field(zda, 4), "31122026") << zda;
  EXPECT_EQ(field(format_gst(fix, options), 1), "235960.50");
  // Outside the leap second nothing changes.
  EXPECT_EQ(field(format_gga(leap_fix(false), options), 1), "235959.50");
}

TEST(LeapSecondSentences, Second60ParsesBack) {
  FormatOptions options;
  const auto sentence = parse_sentence(format_rmc(leap_fix(true), options));
  ASSERT_TRUE(sentence.ok());
  const auto rmc = parse_rmc(sentence.value());
  ASSERT_TRUE(rmc.ok());
  ASSERT_TRUE(rmc.value().time_of_day.has_value());
  EXPECT_EQ(*rmc.value().time_of_day, hours{23} + minutes{59} + seconds{60} + milliseconds{500});
  ASSERT_TRUE(rmc.value().date.has_value());
  EXPECT_EQ(*rmc.value().date, year{2026} / December / 31);
}

}  // namespace leap_second_test
}  // namespace
}  // namespace gpsemu::nmea
