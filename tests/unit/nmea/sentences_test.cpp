// VTG, GLL, ZDA, GST, GSA and GSV formatters, the sentence set and its order, one epoch's text and
// the serial line budget: u-blox manual examples reproduced byte for byte, no-fix forms, NMEA
// 2.3/4.1 differences, several GSA/GSV sentences, and the 82-character limit at the widest values.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "nmea/parse.hpp"
#include "nmea/sentence_set.hpp"
#include "nmea/sentences.hpp"
#include "tests/support/nmea_values.hpp"

namespace gpsemu::nmea {
namespace {
namespace sentences_test {

using namespace std::chrono;
using test::utc;
using test::dm;

FormatOptions options(std::string talker, NmeaVersion version, int minute_decimals = 5, int time_decimals = 2) {
  return FormatOptions{std::move(talker), minute_decimals, time_decimals, version};
}

// The sentences of a text of several, without CR LF.
std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0, end;
  while ((end = text.find("\r\n", start)) != std::string::npos) {
    out.push_back(text.substr(start, end - start));
    start = end + 2;
  }
  EXPECT_EQ(start, text.size()) << "text does not end in CR LF: " << text;
  return out;
}

Fix fix_at(UtcTime t) {
  Fix fix;
  fix.time_utc = t;
  fix.quality = FixQuality::gps;
  fix.dimension = FixDimension::three_d;
  return fix;
}

// u-blox M8 receiver description, NMEA examples.
TEST(NmeaSentences, GllReproducesUbloxExampleAndKeepsTimeWithoutFix) {
  Fix fix = fix_at(utc(2002, 12, 9, 9, 23, 21));
  fix.lat_deg = dm(47, 17.11364);
  fix.lon_deg = dm(8, 33.91565);
  EXPECT_EQ(format_gll(fix, options("GP", NmeaVersion::v4_1)),
            "$GPGLL,4717.11364,N,00833.91565,E,092321.00,A,A*60\r\n");
  fix.quality = FixQuality::none;
  EXPECT_EQ(format_gll(fix, options("GP", NmeaVersion::v4_1)), "$GPGLL,,,,,092321.00,V,N*41\r\n");
  fix.quality = FixQuality::rtk_fixed;
  EXPECT_EQ(parse_sentence(format_gll(fix, options("GN", NmeaVersion::v2_3)))->fields.back(), "R");
}

TEST(NmeaSentences, ZdaReproducesUbloxExampleWithAndWithoutFix) {
  Fix fix = fix_at(utc(2002, 9, 16, 8, 27, 10));
  EXPECT_EQ(format_zda(fix, options("GP", NmeaVersion::v4_1)), "$GPZDA,082710.00,16,09,2002,00,00*64\r\n");
  fix.quality = FixQuality::none;  // the clock is set whether or not there is a fix
  EXPECT_EQ(format_zda(fix, options("GP", NmeaVersion::v4_1)), "$GPZDA,082710.00,16,09,2002,00,00*64\r\n");
  fix.time_utc = utc(2024, 2, 29, 23, 59, 59, 999);
  EXPECT_EQ(parse_sentence(format_zda(fix, options("GN", NmeaVersion::v4_1, 5, 3)))->fields,
            (std::vector<std::string>{"235959.999", "29", "02", "2024", "00", "00"}));
}

TEST(NmeaSentences, VtgCourseKnotsKilometresPerHourAndMode) {
  struct Case {
    double speed_mps;
    std::optional<double> course_deg;
    FixQuality quality;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {10.0, 77.52, FixQuality::gps, "$GPVTG,77.52,T,,M,19.438,N,36.000,K,A*08\r\n"},
      {0.0, std::nullopt, FixQuality::gps, "$GPVTG,,T,,M,0.000,N,0.000,K,A*23\r\n"},  // u-blox: course empty
      {1.0, 359.996, FixQuality::dgps, "$GPVTG,0.00,T,,M,1.944,N,3.600,K,D*35\r\n"},
      {-2.0, 180.0, FixQuality::rtk_float, "$GPVTG,180.00,T,,M,3.888,N,7.200,K,F*3D\r\n"},
      {5.0, 90.0, FixQuality::none, "$GPVTG,,T,,M,,N,,K,N*2C\r\n"},  // no fix: the Telit log's form
  };
  for (const Case& c : cases) {
    Fix fix = fix_at(utc(2024, 1, 1, 0, 0, 0));
    fix.quality = c.quality;
    fix.speed_mps = c.speed_mps;
    fix.course_deg_true = c.course_deg;
    EXPECT_EQ(format_vtg(fix, options("GP", NmeaVersion::v4_1)), c.expected) << c.speed_mps;
  }
}

TEST(NmeaSentences, GstErrorEllipseFromLatLonSigmasAndEmptyWithoutFix) {
  Fix fix = fix_at(utc(2002, 12, 9, 8, 23, 56));
  fix.range_rms_m = 0.4;
  fix.sigma_lat_m = 0.263;
  fix.sigma_lon_m = 0.26;
  fix.sigma_alt_m = 0.3974;
  EXPECT_EQ(format_gst(fix, options("GP", NmeaVersion::v4_1)),
            "$GPGST,082356.00,0.400,0.263,0.260,0.0,0.263,0.260,0.397*54\r\n");
  fix.sigma_lon_m = 1.5;  // east larger: the major axis points east
  const auto east = parse_sentence(format_gst(fix, options("GN", NmeaVersion::v2_3)));
  EXPECT_EQ(east->fields, (std::vector<std::string>{"082356.00", "0.400", "1.500", "0.263", "90.0", "0.263",
                                                    "1.500", "0.397"}));
  fix.sigma_alt_m = 0.0025;  // RTK: millimetres survive
  EXPECT_EQ(parse_sentence(format_gst(fix, options("GP", NmeaVersion::v4_1)))->fields[7], "0.003");
  fix.quality = FixQuality::none;
  EXPECT_EQ(format_gst(fix, options("GP", NmeaVersion::v4_1)), "$GPGST,082356.00,,,,,,,*73\r\n");
}

// u-blox example: 10 in view, these 8 used, in this order.
Fix ublox_sky() {
  Fix fix = fix_at(utc(2002, 12, 9, 9, 27, 25));
  const std::vector<SatelliteInView> sky = {
      {23, 38, 230, 44, true}, {29, 71, 156, 47, true}, {7, 29, 116, 41, true}, {8, 9, 81, 36, true},
      {10, 12, 300, 30, false}, {9, 21, 44, 40, true}, {18, 5, 350, std::nullopt, true}, {2, 3, 10, 20, false},
      {26, 82, 187, 47, true}, {28, 43, 56, 46, true}};
  for (std::size_t i = 0; i < sky.size(); ++i) fix.satellites[i] = sky[i];
  fix.satellites_in_view = static_cast<int>(sky.size());
  fix.satellites_used = 8;
  fix.pdop = 1.94;
  fix.hdop = 1.18;
  fix.vdop = 1.54;
  return fix;
}

TEST(NmeaSentences, GsaReproducesUbloxExampleAndAddsSystemIdIn41) {
  const Fix fix = ublox_sky();
  EXPECT_EQ(format_gsa(fix, options("GP", NmeaVersion::v2_3)),
            "$GPGSA,A,3,23,29,07,08,09,18,26,28,,,,,1.94,1.18,1.54*0D\r\n");
  const auto v41 = parse_sentence(format_gsa(fix, options("GN", NmeaVersion::v4_1)));
  ASSERT_TRUE(v41.ok());
  EXPECT_EQ(v41->talker, "GN");
  EXPECT_EQ(v41->fields.size(), 18u);
  EXPECT_EQ(v41->fields.back(), "1");
}

TEST(NmeaSentences, GsaFixTypeDopCapsAndNoFixForm) {
  Fix fix = ublox_sky();
  fix.dimension = FixDimension::two_d;
  fix.hdop = 250.0;
  auto f = parse_sentence(format_gsa(fix, options("GP", NmeaVersion::v2_3)))->fields;
  EXPECT_EQ(f[1], "2");
  EXPECT_EQ(f[15], "99.99");
  fix.dimension = FixDimension::none;  // not set: written as 3-D
  EXPECT_EQ(parse_sentence(format_gsa(fix, options("GP", NmeaVersion::v2_3)))->fields[1], "3");
  fix.quality = FixQuality::none;  // no PRNs even though some are flagged used
  EXPECT_EQ(format_gsa(fix, options("GN", NmeaVersion::v4_1)), "$GNGSA,A,1,,,,,,,,,,,,,99.99,99.99,99.99,1*33\r\n");
}

TEST(NmeaSentences, GsaSplitsMoreThanTwelveUsedSatellites) {
  Fix fix = fix_at(utc(2024, 1, 1, 0, 0, 0));
  fix.satellites_in_view = 20;
  for (int i = 0; i < 20; ++i) fix.satellites[static_cast<std::size_t>(i)] = {i + 1, 45, 0, 40, i != 3};
  fix.pdop = 1.0;
  fix.hdop = 0.6;
  fix.vdop = 0.8;
  const auto text = format_gsa(fix, options("GN", NmeaVersion::v4_1));
  const auto sentences = lines(text);
  ASSERT_EQ(sentences.size(), 2u) << text;
  const auto first = parse_sentence(sentences[0])->fields;
  const auto second = parse_sentence(sentences[1])->fields;
  EXPECT_EQ(first[2], "01");
  EXPECT_EQ(first[4], "03");
  EXPECT_EQ(first[5], "05");  // 04 is not used
  EXPECT_EQ(first[13], "13");
  EXPECT_EQ(second[2], "14");
  EXPECT_EQ(second[8], "20");
  EXPECT_EQ(second[9], "");
  EXPECT_EQ(second[14], "1.00");
  for (const auto& s : sentences) EXPECT_LE(s.size() + 2, 82u);
}

TEST(NmeaSentences, GsvReproducesUbloxExampleFourPerSentenceNoPadding) {
  const Fix fix = ublox_sky();
  const auto sentences = lines(format_gsv(fix, options("GP", NmeaVersion::v2_3)));
  ASSERT_EQ(sentences.size(), 3u);
  EXPECT_EQ(sentences[0], "$GPGSV,3,1,10,23,38,230,44,29,71,156,47,07,29,116,41,08,09,081,36*7F");
  EXPECT_EQ(sentences[1], "$GPGSV,3,2,10,10,12,300,30,09,21,044,40,18,05,350,,02,03,010,20*7D");
  EXPECT_EQ(sentences[2], "$GPGSV,3,3,10,26,82,187,47,28,43,056,46*77");
}

TEST(NmeaSentences, GsvSignalIdIn41TalkerGpUnderGnAndEmptySky) {
  Fix fix = ublox_sky();
  const auto sentences = lines(format_gsv(fix, options("GN", NmeaVersion::v4_1)));
  ASSERT_EQ(sentences.size(), 3u);
  for (const auto& s : sentences) {
    const auto p = parse_sentence(s);
    ASSERT_TRUE(p.ok()) << s;
    EXPECT_EQ(p->talker, "GP");  // GPS satellites: GPGSV even with talker GN, as u-blox
    EXPECT_EQ(p->fields.back(), "1");
    EXPECT_EQ(p->fields.size() % 4, 0u);  // 3 header fields + 4 per satellite + signal ID
  }
  fix.satellites_in_view = 0;
  EXPECT_EQ(format_gsv(fix, options("GP", NmeaVersion::v4_1)), "$GPGSV,1,1,00,1*64\r\n");
  EXPECT_EQ(format_gsv(fix, options("GL", NmeaVersion::v2_3)), "$GLGSV,1,1,00*65\r\n");
}

TEST(NmeaSentences, SentenceSetKeepsReceiverOrderWhateverTheInsertionOrder) {
  SentenceSet set;
  for (const char* n : {"ZDA", "GGA", "GST", "RMC"}) set.insert(*sentence_type_from_name(n));
  std::string order;
  set.for_each([&](SentenceType t) { order += std::string(sentence_name(t)) + " "; });
  EXPECT_EQ(order, "RMC GGA GST ZDA ");
  std::string def;
  SentenceSet::ublox_default().for_each([&](SentenceType t) { def += std::string(sentence_name(t)) + " "; });
  EXPECT_EQ(def, "RMC VTG GGA GSA GSV GLL ");
  EXPECT_FALSE(sentence_type_from_name("gga").has_value());
  EXPECT_FALSE(sentence_type_from_name("TXT").has_value());
  EXPECT_TRUE(SentenceSet{}.empty());
}

TEST(NmeaSentences, EpochIsTheSetInReceiverOrder) {
  Fix fix = ublox_sky();
  fix.lat_deg = dm(47, 17.11364);
  fix.lon_deg = dm(8, 33.91565);
  FormatOptions o = options("GN", NmeaVersion::v4_1);
  std::string text;
  append_epoch(fix, o, text);
  std::vector<std::string> types;
  for (const auto& l : lines(text)) types.push_back(l.substr(3, 3));
  EXPECT_EQ(types, (std::vector<std::string>{"RMC", "VTG", "GGA", "GSA", "GSV", "GSV", "GSV", "GLL"}));
  o.sentences = SentenceSet{};
  o.sentences.insert(SentenceType::zda);
  o.sentences.insert(SentenceType::gga);
  text.clear();
  append_epoch(fix, o, text);
  EXPECT_EQ(lines(text).size(), 2u);
  EXPECT_EQ(text.substr(3, 3), "GGA");
}

TEST(NmeaSentences, EveryTypeFits82CharactersAtTheWidestValues) {
  Fix fix;
  fix.time_utc = utc(2099, 12, 31, 23, 59, 59, 999);
  fix.quality = FixQuality::rtk_float;
  fix.lat_deg = -dm(89, 59.99999);
  fix.lon_deg = -dm(179, 59.99999);
  fix.speed_mps = 500.0;
  fix.course_deg_true = 359.99;
  fix.hdop = fix.vdop = fix.pdop = 99.99;
  fix.sigma_lat_m = fix.sigma_lon_m = fix.sigma_alt_m = fix.range_rms_m = 999.999;
  fix.satellites_in_view = static_cast<int>(max_satellites);
  for (auto& s : fix.satellites) s = {32, 90, 359, 99, true};
  for (const SentenceType t : all_sentence_types) {
    for (const auto& l : lines(format_sentences(t, fix, options("GN", NmeaVersion::v4_1)))) {
      EXPECT_LE(l.size() + 2, 82u) << l;
      EXPECT_TRUE(parse_sentence(l).ok()) << l;
    }
  }
  EXPECT_EQ(lines(format_sentences(SentenceType::gsv, fix, FormatOptions{})).size(), (max_satellites + 3) / 4);
  EXPECT_EQ(lines(format_sentences(SentenceType::gsa, fix, FormatOptions{})).size(), (max_satellites + 11) / 12);
}

std::string first_line_of(const std::string& text) { return text.substr(0, text.find('\r')); }

Fix multi_gnss_sky() {
  Fix fix;
  fix.quality = FixQuality::gps;
  fix.dimension = FixDimension::three_d;
  fix.hdop = 0.6;
  fix.vdop = 0.9;
  fix.pdop = 1.08;
  const SatelliteInView sats[] = {
      {5, 40, 100, 44, true, GnssSystem::gps, 5},       {46, 30, 200, 38, true, GnssSystem::sbas, 133},
      {70, 50, 45, 45, true, GnssSystem::glonass, 6},   {11, 60, 300, 47, true, GnssSystem::galileo, 11},
      {12, 20, 250, 36, false, GnssSystem::galileo, 12}, {21, 70, 10, 48, true, GnssSystem::beidou, 21},
      {2, 80, 170, 49, true, GnssSystem::qzss, 2},
  };
  for (const auto& s : sats) fix.satellites[static_cast<std::size_t>(fix.satellites_in_view++)] = s;
  return fix;
}

TEST(NmeaSentences, GsvPerSystemWithItsTalkerAndSignalId) {
  const Fix fix = multi_gnss_sky();
  const auto gsv = lines(format_gsv(fix, options("GN", NmeaVersion::v4_1)));
  ASSERT_EQ(gsv.size(), 5u);
  EXPECT_EQ(gsv[0], "$GPGSV,1,1,02,05,40,100,44,46,30,200,38,1*6E") << "SBAS (NMEA 33-64) with GPS";
  EXPECT_EQ(gsv[1].substr(0, 24), "$GLGSV,1,1,01,70,50,045,");
  EXPECT_EQ(gsv[2], "$GAGSV,1,1,02,11,60,300,47,12,20,250,36,7*74") << "Galileo E1: signal 7";
  EXPECT_EQ(gsv[3].substr(0, 6), "$GBGSV");
  EXPECT_EQ(gsv[4].substr(0, 6), "$GQGSV");
  for (const auto& l : gsv) EXPECT_TRUE(parse_sentence(l).ok()) << l;
  // A dual-band receiver (F9P): each system's second signal as its own group, 3 dB weaker.
  FormatOptions dual = options("GN", NmeaVersion::v4_1);
  dual.gsv_second_signal = true;
  const auto both = lines(format_gsv(fix, dual));
  ASSERT_EQ(both.size(), 10u);
  EXPECT_EQ(both[1], "$GPGSV,1,1,01,05,40,100,41,6*57") << "L2 CL; SBAS has no second signal";
  EXPECT_EQ(both[5].substr(both[5].size() - 5, 2), ",2") << "Galileo E5b: " << both[5];
  EXPECT_EQ(both[7].substr(both[7].size() - 5, 2), ",B") << "BeiDou B2I: " << both[7];
  // NMEA 2.3 has no signal ID: one group per system.
  EXPECT_EQ(lines(format_gsv(fix, {.talker = "GN", .version = NmeaVersion::v2_3, .gsv_second_signal = true})).size(), 5u);
}

TEST(NmeaSentences, TimeFieldsAreEmptyUntilTheReceiverKnowsTheTime) {
  Fix fix;
  fix.time_utc = UtcTime{std::chrono::sys_days{std::chrono::year{2024} / 5 / 1}} + std::chrono::hours{12};
  fix.time_valid = false;
  const FormatOptions o = options("GN", NmeaVersion::v4_1);
  const auto rmc = parse_sentence(first_line_of(format_rmc(fix, o)));
  ASSERT_TRUE(rmc.ok());
  EXPECT_EQ(rmc->fields[0], "") << "time";
  EXPECT_EQ(rmc->fields[8], "") << "date";
  EXPECT_EQ(parse_sentence(first_line_of(format_gga(fix, o)))->fields[0], "");
  EXPECT_EQ(parse_sentence(first_line_of(format_gll(fix, o)))->fields[4], "");
  EXPECT_EQ(parse_sentence(first_line_of(format_zda(fix, o)))->fields[0], "");
  EXPECT_EQ(parse_sentence(first_line_of(format_gst(fix, o)))->fields[0], "");
  fix.time_valid = true;
  EXPECT_EQ(parse_sentence(first_line_of(format_rmc(fix, o)))->fields[0], "120000.00");
}

TEST(NmeaSentences, GsaPerSystemWithTheNmea41SystemId) {
  const Fix fix = multi_gnss_sky();
  const auto gsa = lines(format_gsa(fix, options("GN", NmeaVersion::v4_1)));
  ASSERT_EQ(gsa.size(), 5u);
  EXPECT_EQ(gsa[0], "$GNGSA,A,3,05,46,,,,,,,,,,,1.08,0.60,0.90,1*00");
  EXPECT_EQ(gsa[2], "$GNGSA,A,3,11,,,,,,,,,,,,1.08,0.60,0.90,3*05") << "unused E12 not listed";
  for (std::size_t i = 0; i < gsa.size(); ++i) {
    const auto p = parse_sentence(gsa[i]);
    ASSERT_TRUE(p.ok()) << gsa[i];
    EXPECT_EQ(p->fields.back(), std::string(1, static_cast<char>('1' + i))) << gsa[i];
  }
  // One system: one GSA.
  Fix gps = fix;
  gps.satellites_in_view = 1;
  EXPECT_EQ(lines(format_gsa(gps, options("GP", NmeaVersion::v4_1))).size(), 1u);
}

}  // namespace sentences_test
}  // namespace
}  // namespace gpsemu::nmea
