// Parsers: sentence framing and checksum over a table of real-looking valid and invalid lines,
// then GGA and RMC values from published and u-blox sentences, empty fields and malformed fields.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {
namespace parse_test {

using namespace std::chrono;

const std::string published_gga = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47";
const std::string published_rmc = "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A";

// "$body*hh" with a correct checksum, no line end.
std::string framed(const std::string& body) {
  const std::string s = frame(body);
  return s.substr(0, s.size() - 2);
}

Sentence must_parse(const std::string& line) {
  const Result<Sentence> r = parse_sentence(line);
  EXPECT_TRUE(r.ok()) << line << ": " << (r.ok() ? "" : to_string(*r.error()));
  return r.ok() ? r.value() : Sentence{};
}

TEST(NmeaParseSentence, TableOfValidAndInvalidLines) {
  struct Case {
    const char* name;
    std::string line;
    std::optional<ParseError> error;  // nullopt: accepted
  };
  const std::string ok_gga = published_gga;
  const std::string body = ok_gga.substr(0, ok_gga.size() - 3);  // "$GPGGA,...,M,,"
  const std::vector<Case> cases = {
      {"published GGA", ok_gga, std::nullopt},
      {"published RMC", published_rmc, std::nullopt},
      {"CR LF tolerated", ok_gga + "\r\n", std::nullopt},
      {"LF tolerated", ok_gga + "\n", std::nullopt},
      {"lower-case hex accepted", "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6a",
       std::nullopt},
      {"u-blox no fix", "$GPGGA,,,,,,0,00,99.99,,,,,,*48", std::nullopt},
      {"u-blox TXT", "$GPTXT,01,01,02,u-blox ag - www.u-blox.com*50", std::nullopt},
      {"proprietary PUBX", framed("PUBX,00,081350.00,4717.113210,N"), std::nullopt},
      {"bad checksum", body + "*48", ParseError::bad_checksum},
      {"one bit flipped in a field", "$GPGGA,123519,4807.039,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47",
       ParseError::bad_checksum},
      {"missing '*'", body + "47", ParseError::missing_checksum},
      {"truncated mid-field", "$GPGGA,123519,4807.038,N,011", ParseError::missing_checksum},
      {"one hex digit", body + "*4", ParseError::malformed_checksum},
      {"not hex", body + "*4G", ParseError::malformed_checksum},
      {"space after checksum", ok_gga + " ", ParseError::malformed_checksum},
      {"two '*'", "$GPGGA,1*2,3*47", ParseError::malformed_checksum},
      {"no '$'", ok_gga.substr(1), ParseError::missing_dollar},
      {"'!' (AIS) is not NMEA here", "!AIVDM,1,1,,A,13aG?P0P00PD;88MD5MTDww@2<0L,0*5E",
       ParseError::missing_dollar},
      {"empty line", "", ParseError::missing_dollar},
      {"only CR LF", "\r\n", ParseError::missing_dollar},
      {"binary junk", "$GPGGA,\x01\xB5\x62*47", ParseError::bad_character},
      {"'$' inside", "$GPGGA,12$GPRMC*47", ParseError::bad_character},
      {"120 characters accepted", framed("GPTXT," + std::string(110, 'A')), std::nullopt},
      {"121 characters too long", framed("GPTXT," + std::string(111, 'A')), ParseError::too_long},
      {"overlong junk", "$" + std::string(300, '\xB5'), ParseError::too_long},
      {"lower-case address", framed("gpgga,123519"), ParseError::bad_address},
      {"short address", framed("GP,1"), ParseError::bad_address},
      {"empty body", "$*00", ParseError::bad_address},
  };
  for (const Case& c : cases) {
    const Result<Sentence> r = parse_sentence(c.line);
    EXPECT_EQ(r.error(), c.error) << c.name << ": " << (r.ok() ? "ok" : to_string(*r.error()));
  }
  EXPECT_EQ(framed("GPTXT," + std::string(110, 'A')).size(), max_parse_chars);
}

TEST(NmeaParseSentence, SplitsTalkerTypeAndFields) {
  const Sentence gga = must_parse(published_gga + "\r\n");
  EXPECT_EQ(gga.talker, "GP");
  EXPECT_EQ(gga.type, "GGA");
  EXPECT_EQ(gga.fields, (std::vector<std::string>{"123519", "4807.038", "N", "01131.000", "E", "1", "08",
                                                  "0.9", "545.4", "M", "46.9", "M", "", ""}));
  const Sentence pubx = must_parse(framed("PUBX,00,,"));
  EXPECT_EQ(pubx.talker, "P");
  EXPECT_EQ(pubx.type, "UBX");
  EXPECT_EQ(pubx.fields, (std::vector<std::string>{"00", "", ""}));
  EXPECT_TRUE(must_parse(framed("GNGSA")).fields.empty());
}

TEST(NmeaParseGga, PublishedSentenceValues) {
  const Result<GgaData> gga = parse_gga(must_parse(published_gga));
  ASSERT_TRUE(gga.ok());
  EXPECT_EQ(gga->time_of_day, hours{12} + minutes{35} + seconds{19});
  EXPECT_EQ(gga->quality, FixQuality::gps);
  EXPECT_NEAR(*gga->lat_deg, 48.0 + 7.038 / 60.0, 1e-12);
  EXPECT_NEAR(*gga->lon_deg, 11.0 + 31.0 / 60.0, 1e-12);
  EXPECT_EQ(gga->satellites, 8);
  EXPECT_DOUBLE_EQ(*gga->hdop, 0.9);
  EXPECT_DOUBLE_EQ(*gga->alt_msl_m, 545.4);
  EXPECT_DOUBLE_EQ(*gga->geoid_sep_m, 46.9);
  EXPECT_EQ(gga->minute_decimals, 3);
}

TEST(NmeaParseGga, SouthWestNegativeAltitudeAndFractionalTime) {
  const Result<GgaData> gga =
      parse_gga(must_parse(framed("GNGGA,235959.999,3351.40704,S,12225.1640000,W,4,12,0.70,-3.0,M,-32.1,M,1.0,0000")));
  ASSERT_TRUE(gga.ok());
  EXPECT_EQ(gga->time_of_day, hours{23} + minutes{59} + seconds{59} + milliseconds{999});
  EXPECT_NEAR(*gga->lat_deg, -(33.0 + 51.40704 / 60.0), 1e-12);
  EXPECT_NEAR(*gga->lon_deg, -(122.0 + 25.164 / 60.0), 1e-12);
  EXPECT_EQ(gga->quality, FixQuality::rtk_fixed);
  EXPECT_DOUBLE_EQ(*gga->alt_msl_m, -3.0);
  EXPECT_DOUBLE_EQ(*gga->geoid_sep_m, -32.1);
  EXPECT_EQ(gga->minute_decimals, 5);
}

TEST(NmeaParseGga, EmptyFieldsAreNulloptNeverZero) {
  const Result<GgaData> gga = parse_gga(must_parse("$GPGGA,,,,,,0,00,99.99,,,,,,*48"));
  ASSERT_TRUE(gga.ok());
  EXPECT_EQ(gga->time_of_day, std::nullopt);
  EXPECT_EQ(gga->quality, FixQuality::none);
  EXPECT_EQ(gga->lat_deg, std::nullopt);
  EXPECT_EQ(gga->lon_deg, std::nullopt);
  EXPECT_EQ(gga->satellites, 0);  // written as "00"
  EXPECT_EQ(gga->hdop, 99.99);
  EXPECT_EQ(gga->alt_msl_m, std::nullopt);
  EXPECT_EQ(gga->geoid_sep_m, std::nullopt);
  EXPECT_EQ(gga->minute_decimals, 0);
}

TEST(NmeaParseGga, RejectsMalformedFieldsAndWrongSentences) {
  struct Case {
    const char* name;
    std::string line;
    ParseError error;
  };
  const std::vector<Case> cases = {
      {"letter in latitude", framed("GPGGA,123519,48x7.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"minutes 60", framed("GPGGA,123519,4860.000,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"latitude beyond 90", framed("GPGGA,123519,9000.001,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"hemisphere X", framed("GPGGA,123519,4807.038,X,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"value without hemisphere", framed("GPGGA,123519,4807.038,,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"two dots", framed("GPGGA,123519,4807.0.38,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"signed latitude", framed("GPGGA,123519,-4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"altitude 5a5", framed("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,5a5,M,46.9,M,,"),
       ParseError::malformed_field},
      {"altitude nan", framed("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,nan,M,46.9,M,,"),
       ParseError::malformed_field},
      {"altitude in feet", framed("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,F,46.9,M,,"),
       ParseError::malformed_field},
      {"negative satellites", framed("GPGGA,123519,4807.038,N,01131.000,E,1,-8,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"quality 9", framed("GPGGA,123519,4807.038,N,01131.000,E,9,08,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"hour 24", framed("GPGGA,240000,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"short time", framed("GPGGA,1235,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"huge integer", framed("GPGGA,123519,4807.038,N,01131.000,E,1,99999999999,0.9,545.4,M,46.9,M,,"),
       ParseError::malformed_field},
      {"too few fields", framed("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M"),
       ParseError::too_few_fields},
      {"an RMC", published_rmc, ParseError::wrong_type},
  };
  for (const Case& c : cases) {
    const Result<GgaData> gga = parse_gga(must_parse(c.line));
    EXPECT_EQ(gga.error(), c.error) << c.name;
  }
}

TEST(NmeaParseRmc, PublishedNmea20SentenceValues) {
  const Result<RmcData> rmc = parse_rmc(must_parse(published_rmc));
  ASSERT_TRUE(rmc.ok());
  EXPECT_EQ(rmc->time_of_day, hours{12} + minutes{35} + seconds{19});
  EXPECT_EQ(rmc->date, year{1994} / March / day{23});
  EXPECT_TRUE(rmc->status_active);
  EXPECT_NEAR(*rmc->lat_deg, 48.0 + 7.038 / 60.0, 1e-12);
  EXPECT_NEAR(*rmc->lon_deg, 11.0 + 31.0 / 60.0, 1e-12);
  EXPECT_NEAR(*rmc->speed_mps, 22.4 * 1852.0 / 3600.0, 1e-12);
  EXPECT_DOUBLE_EQ(*rmc->course_deg_true, 84.4);
  EXPECT_DOUBLE_EQ(*rmc->magnetic_variation_deg, -3.1);
  EXPECT_EQ(rmc->mode, std::nullopt);
  EXPECT_EQ(rmc->nav_status, std::nullopt);
  EXPECT_EQ(rmc->minute_decimals, 3);
  EXPECT_EQ(utc_time(*rmc), UtcTime{sys_days{year{1994} / March / day{23}}} + hours{12} + minutes{35} + seconds{19});
}

TEST(NmeaParseRmc, Nmea41UbloxAndNoFix) {
  const Result<RmcData> fix =
      parse_rmc(must_parse("$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A,V*2D"));
  ASSERT_TRUE(fix.ok());
  EXPECT_EQ(fix->time_of_day, hours{8} + minutes{35} + seconds{59});
  EXPECT_EQ(fix->date, year{2002} / December / day{9});
  EXPECT_EQ(fix->mode, 'A');
  EXPECT_EQ(fix->nav_status, 'V');
  EXPECT_EQ(fix->magnetic_variation_deg, std::nullopt);
  EXPECT_EQ(fix->minute_decimals, 5);

  const Result<RmcData> none = parse_rmc(must_parse("$GPRMC,235959.99,V,,,,,,,311223,,,N,V*06"));
  ASSERT_TRUE(none.ok());
  EXPECT_FALSE(none->status_active);
  EXPECT_EQ(none->time_of_day, hours{23} + minutes{59} + seconds{59} + milliseconds{990});
  EXPECT_EQ(none->date, year{2023} / December / day{31});
  EXPECT_EQ(none->lat_deg, std::nullopt);
  EXPECT_EQ(none->speed_mps, std::nullopt);
  EXPECT_EQ(none->course_deg_true, std::nullopt);
  EXPECT_EQ(none->mode, 'N');
  EXPECT_EQ(none->minute_decimals, 0);
}

TEST(NmeaParseRmc, DatesPivotAt1980AndMustExist) {
  struct Case {
    std::string date;
    std::optional<year_month_day> expected;  // nullopt: malformed
  };
  const std::vector<Case> cases = {
      {"290224", year{2024} / February / day{29}}, {"010180", year{1980} / January / day{1}},
      {"311279", year{2079} / December / day{31}}, {"010100", year{2000} / January / day{1}},
      {"290223", std::nullopt},                    {"300294", std::nullopt},
      {"001224", std::nullopt},                    {"011324", std::nullopt},
      {"1224", std::nullopt},
  };
  for (const Case& c : cases) {
    const Result<RmcData> rmc = parse_rmc(must_parse(framed("GPRMC,120000,A,,,,,0.0,," + c.date + ",,")));
    if (c.expected) {
      ASSERT_TRUE(rmc.ok()) << c.date;
      EXPECT_EQ(rmc->date, *c.expected) << c.date;
    } else {
      EXPECT_EQ(rmc.error(), ParseError::malformed_field) << c.date;
    }
  }
}

TEST(NmeaParseRmc, RejectsMalformedFields) {
  const std::vector<std::string> bodies = {
      "GPRMC,123519,X,4807.038,N,01131.000,E,022.4,084.4,230394,,",   // status X
      "GPRMC,123519,A,4807.038,N,01131.000,E,-22.4,084.4,230394,,",   // negative speed
      "GPRMC,123519,A,4807.038,N,01131.000,E,22.4,84..4,230394,,",    // course
      "GPRMC,123519,A,4807.038,N,18100.000,E,22.4,84.4,230394,,",     // longitude beyond 180
      "GPRMC,123519,A,4807.038,N,01131.000,E,22.4,84.4,230394,3.1,",  // variation without E/W
      "GPRMC,123519,A,4807.038,N,01131.000,E,22.4,84.4,230394,,,a",   // lower-case mode
      "GPRMC,123519,A,4807.038,N,01131.000,E,22.4,84.4,230394,,,AA",  // two-letter mode
  };
  for (const std::string& body : bodies) {
    EXPECT_EQ(parse_rmc(must_parse(framed(body))).error(), ParseError::malformed_field) << body;
  }
  EXPECT_EQ(parse_rmc(must_parse(framed("GPRMC,123519,A,4807.038,N"))).error(), ParseError::too_few_fields);
  EXPECT_EQ(parse_rmc(must_parse(published_gga)).error(), ParseError::wrong_type);
}

}  // namespace parse_test
}  // namespace
}  // namespace gpsemu::nmea
