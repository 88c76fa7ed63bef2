// The serial line budget: what an 8N1 line carries, the standard bauds, and what a sentence set
// needs, measured on the widest epoch (nmea/line_budget.hpp).
#include "nmea/line_budget.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "nmea/sentence_set.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {
namespace line_budget_test {

FormatOptions options(std::string talker, NmeaVersion version, int minute_decimals = 5, int time_decimals = 2) {
  return FormatOptions{std::move(talker), minute_decimals, time_decimals, version};
}

TEST(LineBudgetTest, DesignExampleGgaRmcAt10HzDoesNotFit9600AndNames19200) {
  // docs/design.md: 10 Hz GGA+RMC (~145 bytes) needs >= 14 500 baud; with the 90 % margin 16 111.
  const LineBudget b = line_budget(145, 10.0);
  EXPECT_FALSE(b.fits(9600, kLineBudgetMargin));
  EXPECT_DOUBLE_EQ(b.bytes_per_second, 1450.0);
  EXPECT_DOUBLE_EQ(line_bytes_per_second(9600), 960.0);
  EXPECT_DOUBLE_EQ(line_bytes_per_second(9600) * kLineBudgetMargin, 864.0);
  EXPECT_EQ(smallest_standard_baud(b, kLineBudgetMargin), 19200);
}

TEST(LineBudgetTest, MarginDecidesAtTheEdge) {
  EXPECT_TRUE(line_budget(432, 1.0).fits(4800, kLineBudgetMargin));  // exactly 90 % of 480 bytes/s
  EXPECT_FALSE(line_budget(433, 1.0).fits(4800, kLineBudgetMargin));
  EXPECT_TRUE(line_budget(480, 1.0).fits(4800));  // no margin: the whole line
}

TEST(LineBudgetTest, NothingFitsBeyond921600) {
  const LineBudget b = line_budget(10000, 50.0);
  EXPECT_FALSE(b.fits(115200, kLineBudgetMargin));
  EXPECT_EQ(smallest_standard_baud(b, kLineBudgetMargin), 0);
}

TEST(LineBudgetTest, StandardBauds) {
  for (const int baud : {4800, 9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600}) {
    EXPECT_TRUE(is_standard_baud(baud)) << baud;
  }
  for (const int baud : {0, 300, 1200, 2400, 14400, 250000, 1000000}) EXPECT_FALSE(is_standard_baud(baud)) << baud;
}

TEST(NmeaSentences, LineBudgetOfGgaRmcAt10HzNeedsMoreThan9600Baud) {
  FormatOptions o = options("GP", NmeaVersion::v4_1);
  o.sentences = SentenceSet{};
  o.sentences.insert(SentenceType::gga);
  o.sentences.insert(SentenceType::rmc);
  const LineBudget b = line_budget(o, 12, 10, 10.0);
  // The widest GGA (90: altitude -12345.6, RTK's differential age 999.9 and station 4095) and RMC (78).
  EXPECT_EQ(b.bytes_per_epoch, 168u);
  EXPECT_DOUBLE_EQ(b.bytes_per_second, 1680.0);
  EXPECT_DOUBLE_EQ(b.min_baud, 16800.0);
  EXPECT_FALSE(b.fits(9600));
  EXPECT_TRUE(b.fits(19200));
  EXPECT_EQ(smallest_standard_baud(b), 19200);
  EXPECT_EQ(smallest_standard_baud(line_budget(o, 12, 10, 1.0)), 4800);
}

TEST(NmeaSentences, LineBudgetGrowsWithSatellitesInViewAndRate) {
  const FormatOptions o = options("GN", NmeaVersion::v4_1);  // u-blox default set
  const LineBudget few = line_budget(o, 4, 4, 1.0);
  const LineBudget many = line_budget(o, 15, 11, 1.0);
  EXPECT_GT(many.bytes_per_epoch, few.bytes_per_epoch + 3 * 60);  // three more GSV sentences
  EXPECT_DOUBLE_EQ(line_budget(o, 15, 11, 10.0).bytes_per_second, 10.0 * many.bytes_per_epoch);
  EXPECT_EQ(smallest_standard_baud(line_budget(o, 15, 11, 10.0)), 115200);
  EXPECT_EQ(smallest_standard_baud(line_budget(o, 15, 11, 1.0)), 9600);
  EXPECT_EQ(smallest_standard_baud(line_budget(o, 32, 32, 50.0)), 921600);
  // Counts beyond the limits are clamped, used to at most in view.
  EXPECT_EQ(line_budget(o, 99, 99, 1.0).bytes_per_epoch, line_budget(o, 64, 64, 1.0).bytes_per_epoch);
}

TEST(NmeaSentences, LineBudgetOfSeveralSystemsCoversAGsvGroupAndAGsaOfEach) {
  const FormatOptions o = options("GN", NmeaVersion::v4_1);  // u-blox default set
  const std::vector<SystemSatellites> two{{GnssSystem::gps, 13}, {GnssSystem::glonass, 10}};
  const LineBudget split = line_budget(o, two, 19, 1.0);
  // One GPS group of 23 (6 GSV) understates GPS 13 (4 GSV) + GLONASS 10 (3 GSV) and a second GSA.
  EXPECT_GT(split.bytes_per_epoch, line_budget(o, 23, 19, 1.0).bytes_per_epoch);
  // A real epoch of that sky, every field as wide as a receiver writes it, fits the budget.
  Fix fix = widest_fix(two, 19);
  ASSERT_EQ(fix.satellites_in_view, 23);
  EXPECT_EQ(fix.satellites_used, 19);
  int gps_used = 0, glonass_used = 0;
  for (int i = 0; i < fix.satellites_in_view; ++i) {
    const SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
    (sat.system == GnssSystem::gps ? gps_used : glonass_used) += sat.used ? 1 : 0;
  }
  EXPECT_EQ(gps_used, 11);  // in proportion: ceil(19 x 13 / 23)
  EXPECT_EQ(glonass_used, 8);
  std::string epoch;
  append_epoch(fix, o, epoch);
  EXPECT_EQ(epoch.size(), split.bytes_per_epoch);
  EXPECT_NE(epoch.find("$GLGSV,3,3,"), std::string::npos) << epoch;
  // One system given as a list is the single-group budget.
  const std::vector<SystemSatellites> one{{GnssSystem::gps, 15}};
  EXPECT_EQ(line_budget(o, one, 11, 1.0).bytes_per_epoch, line_budget(o, 15, 11, 1.0).bytes_per_epoch);
}

TEST(NmeaSentences, LineBudgetCountsTheDifferentialFieldsRtkAddsToGga) {
  FormatOptions o = options("GP", NmeaVersion::v4_1);
  o.sentences = SentenceSet{};
  o.sentences.insert(SentenceType::gga);
  const Fix fix = widest_fix(12, 10);
  std::string gga;
  append_epoch(fix, o, gga);
  EXPECT_NE(gga.find(",999.9,4095*"), std::string::npos) << gga;
  // Without them the sentence is 9 characters shorter: the budget covers a receiver with corrections.
  Fix plain = fix;
  plain.diff_age_s.reset();
  plain.diff_station_id.reset();
  std::string without;
  append_epoch(plain, o, without);
  EXPECT_EQ(line_budget(o, 12, 10, 1.0).bytes_per_epoch, without.size() + 9);
}

}  // namespace line_budget_test
}  // namespace
}  // namespace gpsemu::nmea
