// Format then parse: GGA and RMC recover latitude/longitude within half a unit of the output
// resolution, the time truncated to the written decimals, the date and the speed.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"
#include "tests/support/nmea_values.hpp"

namespace gpsemu::nmea {
namespace {
namespace roundtrip_test {

using namespace std::chrono;
using test::mps_per_knot;

// Half a unit of the last minute decimal, in degrees, plus floating-point slack.
double half_unit_deg(int minute_decimals) { return 0.5 / (60.0 * std::pow(10.0, minute_decimals)) + 1e-12; }

std::vector<Fix> fixes() {
  std::vector<Fix> out;
  std::mt19937_64 engine(20240229);
  std::uniform_real_distribution<double> lat(-90.0, 90.0);
  std::uniform_real_distribution<double> lon(-180.0, 180.0);
  // Two-digit years are read as 1980..2079.
  const UtcTime first = UtcTime{sys_days{year{1980} / January / day{1}}};
  const long long span_ms = (sys_days{year{2080} / January / day{1}} - sys_days{year{1980} / January / day{1}}) / milliseconds{1};
  std::uniform_int_distribution<long long> ms(0, span_ms - 1);
  const std::vector<std::pair<double, double>> edges = {
      {0.0, 0.0},   {90.0, 180.0 - 1e-9}, {-90.0, -180.0}, {89.99999999, 179.99999999},
      {-1e-9, -1e-9}, {47.0 + 59.9999996 / 60.0, -(7.0 + 59.9999996 / 60.0)},
  };
  for (int i = 0; i < 200; ++i) {
    Fix fix;
    fix.quality = FixQuality::gps;
    fix.time_utc = first + milliseconds{ms(engine)};
    if (i < static_cast<int>(edges.size())) {
      fix.lat_deg = edges[static_cast<std::size_t>(i)].first;
      fix.lon_deg = edges[static_cast<std::size_t>(i)].second;
    } else {
      fix.lat_deg = lat(engine);
      fix.lon_deg = lon(engine);
    }
    fix.speed_mps = i * 0.37;
    fix.course_deg_true = std::fmod(i * 7.3, 360.0);
    fix.alt_msl_m = i * 3.3 - 100.0;
    fix.satellites_used = i % 40;
    fix.hdop = 0.5 + i * 0.01;
    out.push_back(fix);
  }
  return out;
}

TEST(NmeaRoundTrip, PositionTimeDateSpeedSurviveFormatThenParse) {
  for (const int minute_decimals : {4, 5, 7}) {
    for (const int time_decimals : {0, 2, 3}) {
      const FormatOptions options{"GN", minute_decimals, time_decimals, NmeaVersion::v4_1};
      const milliseconds time_unit{time_decimals == 0 ? 1000 : time_decimals == 2 ? 10 : 1};
      for (const Fix& fix : fixes()) {
        const std::string gga_text = format_gga(fix, options);
        const std::string rmc_text = format_rmc(fix, options);
        const Result<Sentence> gga_sentence = parse_sentence(gga_text);
        const Result<Sentence> rmc_sentence = parse_sentence(rmc_text);
        ASSERT_TRUE(gga_sentence.ok()) << gga_text;
        ASSERT_TRUE(rmc_sentence.ok()) << rmc_text;
        const Result<GgaData> gga = parse_gga(*gga_sentence);
        const Result<RmcData> rmc = parse_rmc(*rmc_sentence);
        ASSERT_TRUE(gga.ok()) << gga_text;
        ASSERT_TRUE(rmc.ok()) << rmc_text;

        EXPECT_NEAR(*gga->lat_deg, fix.lat_deg, half_unit_deg(minute_decimals)) << gga_text;
        EXPECT_NEAR(*gga->lon_deg, fix.lon_deg, half_unit_deg(minute_decimals)) << gga_text;
        EXPECT_EQ(*rmc->lat_deg, *gga->lat_deg);
        EXPECT_EQ(*rmc->lon_deg, *gga->lon_deg);
        EXPECT_EQ(gga->minute_decimals, minute_decimals);
        EXPECT_EQ(gga->quality, FixQuality::gps);
        EXPECT_EQ(gga->satellites, fix.satellites_used);

        const auto day = floor<days>(fix.time_utc);
        const auto written_time = floor<milliseconds>(fix.time_utc - day) / time_unit * time_unit;
        EXPECT_EQ(gga->time_of_day, written_time) << gga_text;
        EXPECT_EQ(rmc->date, year_month_day{day}) << rmc_text;
        EXPECT_EQ(utc_time(*rmc), UtcTime{day} + written_time);
        EXPECT_NEAR(*rmc->speed_mps, fix.speed_mps, 0.0005 * mps_per_knot + 1e-12) << rmc_text;
        EXPECT_NEAR(*rmc->course_deg_true, *fix.course_deg_true, 0.005 + 1e-9) << rmc_text;
        EXPECT_TRUE(rmc->status_active);
        EXPECT_EQ(rmc->mode, 'A');
      }
    }
  }
}

}  // namespace roundtrip_test
}  // namespace
}  // namespace gpsemu::nmea
