// HDT and THS: formatted from a fix's heading (empty / mode V without one), in the sentence set
// after the u-blox sentences, parsed back from real-shaped sentences, and read the way
// ArduPilot's AP_GPS_NMEA reads them (its term parser for HDT/THS, replayed below).
#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "nmea/heading.hpp"
#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {
namespace heading_test {

Fix fix_with_heading(std::optional<double> heading_deg) {
  Fix fix;
  fix.quality = FixQuality::rtk_fixed;
  fix.dimension = FixDimension::three_d;
  fix.heading_deg_true = heading_deg;
  return fix;
}

FormatOptions talker(std::string t) {
  FormatOptions o;
  o.talker = std::move(t);
  return o;
}

TEST(Heading, HdtAndThsCarryTheHeadingWithTwoDecimals) {
  const Fix fix = fix_with_heading(274.0712);
  EXPECT_EQ(format_hdt(fix, talker("GP")), "$GPHDT,274.07,T*03\r\n");
  EXPECT_EQ(format_ths(fix, talker("GP")), "$GPTHS,274.07,A*01\r\n");
}

TEST(Heading, WithoutAHeadingHdtIsEmptyAndThsSaysNotValid) {
  EXPECT_EQ(format_hdt(fix_with_heading(std::nullopt), talker("GN")), "$GNHDT,,T*05\r\n");
  EXPECT_EQ(format_ths(fix_with_heading(std::nullopt), talker("GN")), "$GNTHS,,V*10\r\n");
  Fix no_fix = fix_with_heading(12.0);  // a heading needs both antennas' solutions
  no_fix.quality = FixQuality::none;
  EXPECT_EQ(format_ths(no_fix, talker("GN")), "$GNTHS,,V*10\r\n");
}

TEST(Heading, RoundingStaysBelow360) {
  EXPECT_EQ(format_hdt(fix_with_heading(359.996), talker("GP")).substr(0, 14), "$GPHDT,0.00,T*");
}

TEST(Heading, SentenceSetWritesThemLastWhenAsked) {
  FormatOptions o = talker("GN");
  o.sentences = {};
  for (const char* n : {"THS", "GGA", "HDT"}) o.sentences.insert(*sentence_type_from_name(n));
  std::string text;
  append_epoch(fix_with_heading(10.0), o, text);
  EXPECT_EQ(text.find("$GNGGA"), 0u);
  const auto hdt = text.find("$GNHDT,10.00,T*");
  const auto ths = text.find("$GNTHS,10.00,A*");
  ASSERT_NE(hdt, std::string::npos);
  ASSERT_NE(ths, std::string::npos);
  EXPECT_LT(hdt, ths);
  EXPECT_FALSE(SentenceSet::ublox_default().contains(SentenceType::hdt));
}

struct Real {
  const char* line;
  std::optional<double> heading;
  char mode;
};

TEST(Heading, ParsesRealShapedSentences) {
  for (const Real& r : {Real{"$GPHDT,274.07,T*03", 274.07, 'T'}, Real{"$HEHDT,359.9,T*29", 359.9, 'T'},
                        Real{"$GNHDT,,T*05", std::nullopt, 'T'}}) {
    const auto s = parse_sentence(r.line);
    ASSERT_TRUE(s) << r.line;
    const auto h = parse_hdt(*s);
    ASSERT_TRUE(h) << r.line;
    EXPECT_EQ(h->heading_deg_true, r.heading) << r.line;
    EXPECT_EQ(h->mode, r.mode);
  }
  for (const Real& r : {Real{"$GPTHS,77.52,A*30", 77.52, 'A'}, Real{"$GNTHS,,V*10", std::nullopt, 'V'},
                        Real{"$GPTHS,12.30,E*33", 12.3, 'E'}}) {
    const auto s = parse_sentence(r.line);
    ASSERT_TRUE(s) << r.line;
    const auto h = parse_ths(*s);
    ASSERT_TRUE(h) << r.line;
    EXPECT_EQ(h->heading_deg_true, r.heading) << r.line;
    EXPECT_EQ(h->mode, r.mode);
  }
}

TEST(Heading, RefusesWhatIsNotAHeading) {
  const auto parsed = [](const std::string& body, bool ths) {
    const auto s = parse_sentence(frame(body).substr(0, frame(body).size() - 2));
    EXPECT_TRUE(s) << body;
    return ths ? parse_ths(*s).error() : parse_hdt(*s).error();
  };
  EXPECT_EQ(parsed("GPHDT,361.0,T", false), ParseError::malformed_field);
  EXPECT_EQ(parsed("GPHDT,-1,T", false), ParseError::malformed_field);
  EXPECT_EQ(parsed("GPHDT,12.x,T", false), ParseError::malformed_field);
  EXPECT_EQ(parsed("GPHDT,12.0,M", false), ParseError::malformed_field);
  EXPECT_EQ(parsed("GPHDT,12.0", false), ParseError::too_few_fields);
  EXPECT_EQ(parsed("GPTHS,12.0,Q", true), ParseError::malformed_field);
  EXPECT_EQ(parsed("GPHDT,12.0,T", true), ParseError::wrong_type);
}

// ArduPilot's AP_GPS_NMEA for HDT and THS (libraries/AP_GPS/AP_GPS_NMEA.cpp): terms split at ','
// and '*'; term 0 selects the sentence by the letters after the talker (HDT presumes the data
// good, THS needs term 2 == 'A'); term 1, when not empty, is the yaw in hundredths of a degree
// (_parse_decimal_100: the integer part and at most two decimals); a checked sentence then sets
// gps_yaw and have_gps_yaw when the data is good, and a bad THS clears have_gps_yaw.
struct ApYaw {
  bool have_gps_yaw = false;
  double gps_yaw_deg = 0.0;
  long new_gps_yaw = 0;  // kept between sentences, as the driver's member
};

long ap_parse_decimal_100(const std::string& term) {
  const char* p = term.c_str();
  long ret = 100 * std::strtol(p, nullptr, 10);
  while (*p >= '0' && *p <= '9') ++p;
  if (*p == '.' && p[1] >= '0' && p[1] <= '9') {
    ret += 10 * (p[1] - '0');
    if (p[2] >= '0' && p[2] <= '9') ret += p[2] - '0';
  }
  return ret;
}

void ap_feed(ApYaw& ap, const std::string& sentence) {
  const std::string body = sentence.substr(1, sentence.find('*') - 1);
  std::vector<std::string> terms;
  std::size_t start = 0;
  for (std::size_t comma; (comma = body.find(',', start)) != std::string::npos; start = comma + 1) {
    terms.push_back(body.substr(start, comma - start));
  }
  terms.push_back(body.substr(start));
  const std::string type = terms[0].substr(2);
  bool good = type == "HDT";
  for (std::size_t i = 1; i < terms.size(); ++i) {
    if (terms[i].empty()) continue;
    if (i == 1) ap.new_gps_yaw = ap_parse_decimal_100(terms[i]);
    if (type == "THS" && i == 2) good = terms[i][0] == 'A';
  }
  if (good) {
    ap.gps_yaw_deg = static_cast<double>(ap.new_gps_yaw) * 0.01;
    ap.have_gps_yaw = true;
  } else if (type == "THS") {
    ap.have_gps_yaw = false;
  }
}

TEST(Heading, ArduPilotReadsTheHeadingAndTheLossOfIt) {
  ApYaw ap;
  ap_feed(ap, format_ths(fix_with_heading(123.456), talker("GN")));
  EXPECT_TRUE(ap.have_gps_yaw);
  EXPECT_NEAR(ap.gps_yaw_deg, 123.46, 1e-9);  // written rounded to 2 decimals, read to 0.01
  ap_feed(ap, format_hdt(fix_with_heading(7.5), talker("GN")));
  EXPECT_TRUE(ap.have_gps_yaw);
  EXPECT_NEAR(ap.gps_yaw_deg, 7.5, 1e-9);
  ap_feed(ap, format_ths(fix_with_heading(std::nullopt), talker("GN")));
  EXPECT_FALSE(ap.have_gps_yaw);  // THS mode V: ArduPilot drops the GPS yaw
  // An empty HDT is "good" to ArduPilot and repeats the last yaw: why docs/heading.md says THS.
  ap_feed(ap, format_hdt(fix_with_heading(std::nullopt), talker("GN")));
  EXPECT_TRUE(ap.have_gps_yaw);
  EXPECT_NEAR(ap.gps_yaw_deg, 7.5, 1e-9);
}

}  // namespace heading_test
}  // namespace
}  // namespace gpsemu::nmea
