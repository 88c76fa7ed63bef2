// The replay log reader (emulator/replay/replay_log.hpp): epochs from a messy byte stream, what
// is skipped and counted, the log's timeline (gaps, steps back, midnight), --from/--to, and
// retiming. Pure: logs are generated here.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "emulator/replay/replay_log.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::replay {
namespace {
namespace log_test {

using namespace std::chrono;

/// "$body*hh" + ending.
std::string s(const std::string& body, const std::string& ending = "\r\n") {
  return fmt::format("${}*{:02X}{}", body, nmea::checksum(body), ending);
}

std::string gga(const std::string& time) { return s(fmt::format("GPGGA,{},4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,", time)); }
std::string rmc(const std::string& time, const std::string& date = "010524") {
  return s(fmt::format("GPRMC,{},A,4304.35012,N,08924.75027,W,0.000,,{},,,A,V", time, date));
}
std::string gsa() { return s("GPGSA,A,3,01,02,03,04,,,,,,,,,1.5,0.9,1.2"); }
std::string gsv() { return s("GPGSV,1,1,04,01,40,083,46,02,17,308,41,03,07,344,39,04,22,228,45"); }

nanoseconds tod(int h, int m, double sec) {
  return hours(h) + minutes(m) + nanoseconds{static_cast<std::int64_t>(std::llround(sec * 1e9))};
}

/// Every sentence of `text` checks out.
bool checksums_ok(const std::string& text) {
  std::size_t start = 0;
  while (start < text.size()) {
    const auto end = text.find('\n', start);
    const std::string line = text.substr(start, end - start);
    if (!nmea::parse_sentence(line).ok()) return false;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return true;
}

TEST(ReplayLog, EpochsAreRunsOfSentencesSharingATimeWithUntimedOnesWhereTheySit) {
  const std::string e1 = rmc("120000.00") + s("GPVTG,,T,,M,0.000,N,0.000,K,A") + gga("120000.00") + gsa() + gsv();
  const std::string e2 = rmc("120001.00") + s("GPVTG,,T,,M,0.000,N,0.000,K,A") + gga("120001.00") + gsa() + gsv();
  const ReplayLog log = parse_replay_log(e1 + e2);
  ASSERT_EQ(log.epochs.size(), 2u);
  EXPECT_EQ(log.epochs[0].bytes, e1);
  EXPECT_EQ(log.epochs[1].bytes, e2);
  EXPECT_EQ(log.epochs[0].sentences.size(), 5u);
  EXPECT_EQ(*log.epochs[0].time_of_day, tod(12, 0, 0));
  EXPECT_EQ(log.epochs[1].log_time - log.epochs[0].log_time, seconds(1));
  EXPECT_EQ(log.period, seconds(1));
  EXPECT_EQ(log.counts.untimed_epochs, 0u);
}

TEST(ReplayLog, LeadingSentencesWithoutATimeJoinTheFirstEpoch) {
  // A log that starts in the middle of an epoch: the GSA/GSV before the first GGA are part of it.
  const std::string lead = gsa() + gsv();
  const std::string e1 = gga("120000.00") + rmc("120000.00");
  const ReplayLog log = parse_replay_log(lead + e1 + gga("120001.00"));
  ASSERT_EQ(log.epochs.size(), 2u);
  EXPECT_EQ(log.epochs[0].bytes, lead + e1);
  EXPECT_EQ(*log.epochs[0].time_of_day, tod(12, 0, 0));
}

TEST(ReplayLog, BinaryBadChecksumsMalformedAndCommentsAreSkippedAndCounted) {
  const std::string e1 = gga("120000.00") + rmc("120000.00");
  const std::string e2 = gga("120001.00") + rmc("120001.00");
  std::string bad = gga("120000.50");
  bad[bad.size() - 3] = bad[bad.size() - 3] == '0' ? '1' : '0';  // wrong checksum digit
  const std::string ubx("\xb5\x62\x01\x07\x5c\x00\x24\x10\x00\xff\xfe\x0a\x0d", 13);
  const std::string text = "# a gpsd log header\n" + ubx + e1 + bad + "$GPGGA,12000" + "\x01\x02" + "\r\n" + ubx +
                           "# sent 2024-05-01T12:00:01.050000Z\n" + e2 + "garbage\r\n";
  const ReplayLog log = parse_replay_log(text);
  ASSERT_EQ(log.epochs.size(), 2u);
  EXPECT_EQ(log.epochs[0].bytes, e1) << "content unchanged, junk left out";
  EXPECT_EQ(log.epochs[1].bytes, e2);
  EXPECT_EQ(log.counts.stream.sentences_ok, 4u);
  EXPECT_EQ(log.counts.stream.bad_checksum, 1u);
  EXPECT_EQ(log.counts.stream.malformed, 1u);
  EXPECT_EQ(log.counts.stream.comment_lines, 2u);
  EXPECT_GT(log.counts.stream.garbage_bytes, 2 * ubx.size() - 4);
}

TEST(ReplayLog, LineEndingsAreKeptAsRecordedAndAFinalSentenceNeedsNone) {
  const std::string lf = s("GPGGA,120000,,,,,0,00,,,,,,,", "\n");
  const std::string cr = s("GPRMC,120000,V,,,,,,,010524,,,N", "\r");
  const std::string last = s("GPGGA,120001,,,,,0,00,,,,,,,", "");
  const ReplayLog log = parse_replay_log(lf + cr + last);
  ASSERT_EQ(log.epochs.size(), 2u);
  EXPECT_EQ(log.epochs[0].bytes, lf + cr);
  EXPECT_EQ(log.epochs[1].bytes, last);
  EXPECT_EQ(log.epochs[0].time_of_day, tod(12, 0, 0));
}

TEST(ReplayLog, NoFixEpochsWithoutTimeAreSplitAtARepeatedSentenceAndPlacedOnePeriodApart) {
  // A Telit-like start: no-fix epochs with empty time fields, then fixes at 1 Hz.
  const std::string nofix = s("GPGGA,,,,,,0,,,,M,,M,,") + s("GPGSA,A,1,,,,,,,,,,,,,,,") + s("GPRMC,,V,,,,,,,,,,N");
  const std::string fix1 = gga("105153.408") + rmc("105153.408", "120319");
  const std::string fix2 = gga("105154.408") + rmc("105154.408", "120319");
  const std::string fix3 = gga("105155.408") + rmc("105155.408", "120319");
  const ReplayLog log = parse_replay_log(nofix + nofix + nofix + fix1 + fix2 + nofix + fix3);
  ASSERT_EQ(log.epochs.size(), 7u);
  for (const std::size_t i : {0u, 1u, 2u, 5u}) {
    EXPECT_EQ(log.epochs[i].bytes, nofix) << i;
    EXPECT_FALSE(log.epochs[i].time_of_day) << i;
  }
  EXPECT_EQ(log.counts.untimed_epochs, 4u);
  EXPECT_EQ(log.period, seconds(1));
  const nanoseconds t0 = tod(10, 51, 53.408);
  EXPECT_EQ(log.epochs[0].log_time, t0 - seconds(3));
  EXPECT_EQ(log.epochs[2].log_time, t0 - seconds(1));
  EXPECT_EQ(log.epochs[3].log_time, t0);
  EXPECT_EQ(log.epochs[5].log_time, t0 + seconds(2)) << "one period after the previous epoch";
  EXPECT_EQ(log.epochs[6].log_time, t0 + seconds(2));
}

TEST(ReplayLog, MidnightRolloverAddsADayAndStepsBackAndGapsAreCounted) {
  const ReplayLog log = parse_replay_log(gga("235958.00") + gga("235959.00") + gga("000000.00") + gga("000003.00") +
                                         gga("000002.50") + gga("000004.00"));
  ASSERT_EQ(log.epochs.size(), 6u);
  EXPECT_EQ(log.counts.rollovers, 1u);
  EXPECT_EQ(log.counts.steps_back, 1u);
  EXPECT_EQ(log.counts.gaps, 1u);
  EXPECT_EQ(log.counts.longest_gap, seconds(3));
  EXPECT_EQ(log.epochs[2].log_time, hours(24));
  EXPECT_EQ(log.epochs[3].log_time, hours(24) + seconds(3));
  EXPECT_EQ(log.epochs[4].log_time, hours(24) + milliseconds(2500)) << "kept as recorded";
  EXPECT_EQ(log.epochs[5].log_time - log.epochs[0].log_time, seconds(6));
}

TEST(ReplayLog, BadTimeFieldsAreCountedAndTheSentenceKept) {
  const ReplayLog log = parse_replay_log(gga("120000.00") + gga("12xx00.00") + gga("120001.00"));
  EXPECT_EQ(log.counts.bad_time_fields, 1u);
  // The bad one has no time: it starts a no-time epoch (GPGGA repeats).
  ASSERT_EQ(log.epochs.size(), 3u);
  EXPECT_FALSE(log.epochs[1].time_of_day);
}

TEST(ReplayLog, TimeOfDayFieldsParse) {
  EXPECT_EQ(parse_time_of_day("123456"), tod(12, 34, 56));
  EXPECT_EQ(parse_time_of_day("123456.7"), tod(12, 34, 56.7));
  EXPECT_EQ(parse_time_of_day("000000.408"), milliseconds(408));
  EXPECT_EQ(parse_time_of_day("235960.00"), tod(23, 59, 60)) << "leap second";
  EXPECT_FALSE(parse_time_of_day("12345"));
  EXPECT_FALSE(parse_time_of_day("246000"));
  EXPECT_FALSE(parse_time_of_day("126000"));
  EXPECT_FALSE(parse_time_of_day("123456,7"));
  EXPECT_FALSE(parse_time_of_day("12:34:56"));
}

TEST(ReplayLog, LogPositionsParse) {
  EXPECT_EQ(parse_log_position("from", "12"), LogPosition{std::int64_t{12}});
  EXPECT_EQ(parse_log_position("from", "12:00:05"), LogPosition{nanoseconds{tod(12, 0, 5)}});
  EXPECT_EQ(parse_log_position("from", "23:59:59.25"), LogPosition{nanoseconds{tod(23, 59, 59.25)}});
  for (const char* bad : {"", "-1", "12:60:00", "24:00:00", "1:2:3", "12:00:00.", "12:00:00x", "abc", "12:00"}) {
    EXPECT_THROW((void)parse_log_position("from", bad), std::invalid_argument) << bad;
  }
  try {
    (void)parse_log_position("to", "noon");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("to: expected a time of day hh:mm:ss[.ss]"), std::string::npos) << e.what();
  }
}

TEST(ReplayLog, FromAndToSelectByTimeOfDayAcrossMidnightOrByIndex) {
  std::string text;
  for (const char* t : {"235957.00", "235958.00", "235959.00", "000000.00", "000001.00", "000002.00"}) text += gga(t);
  const ReplayLog log = parse_replay_log(text);
  auto range = [&](std::optional<std::string> from, std::optional<std::string> to) {
    const auto r = select_range(log, from ? std::optional{parse_log_position("from", *from)} : std::nullopt,
                                to ? std::optional{parse_log_position("to", *to)} : std::nullopt);
    return std::pair{r.first, r.last};
  };
  EXPECT_EQ(range(std::nullopt, std::nullopt), (std::pair<std::size_t, std::size_t>{0, 5}));
  EXPECT_EQ(range("23:59:58", "00:00:01"), (std::pair<std::size_t, std::size_t>{1, 4}));
  EXPECT_EQ(range("23:59:58.5", std::nullopt), (std::pair<std::size_t, std::size_t>{2, 5}));
  EXPECT_EQ(range("00:00:00", "00:00:00.5"), (std::pair<std::size_t, std::size_t>{3, 3}));
  EXPECT_EQ(range("2", "4"), (std::pair<std::size_t, std::size_t>{2, 4}));
  EXPECT_THROW((void)range("6", std::nullopt), std::invalid_argument);
  EXPECT_THROW((void)range("4", "2"), std::invalid_argument);
  EXPECT_THROW((void)range("00:00:03", std::nullopt), std::invalid_argument);
  EXPECT_THROW((void)range("00:00:01.5", "00:00:01.6"), std::invalid_argument);
}

TEST(ReplayLog, RetimeRewritesTimesAndDatesKeepsDecimalsAndRecomputesChecksums) {
  const std::string text = rmc("105153.408", "120319") + s("GPVTG,303.60,T,,M,0.13,N,0.25,K,A") +
                           gga("105153.408") + s("GPGLL,5050.4122,N,00420.8265,E,105153.408,A,A", "\n") +
                           s("GPZDA,105153.40,12,03,2019,00,00") + s("GPGST,105153,1.2,,,,0.9,0.8,1.9");
  // Times of different precision (one per sentence type) in one epoch.
  const ReplayLog log = parse_replay_log(text);
  LogEpoch epoch;
  for (const auto& e : log.epochs) {
    for (const auto& sentence : e.sentences) epoch.sentences.push_back(sentence);
  }
  ASSERT_EQ(epoch.sentences.size(), 6u);
  const UtcNs when = parse_iso8601_utc("2024-02-29T23:59:59.9996Z");
  const std::string out = retime_epoch(epoch, when);
  EXPECT_TRUE(checksums_ok(out)) << out;
  const auto lines = [&] {
    std::vector<std::string> v;
    std::size_t start = 0, nl;
    while ((nl = out.find('\n', start)) != std::string::npos) {
      v.push_back(out.substr(start, nl + 1 - start));
      start = nl + 1;
    }
    return v;
  }();
  ASSERT_EQ(lines.size(), 6u) << out;
  // 3 decimals: 23:59:59.9996 rounds up to the next day, 1 March.
  EXPECT_EQ(lines[0].substr(0, lines[0].find('*')), "$GPRMC,000000.000,A,4304.35012,N,08924.75027,W,0.000,,010324,,,A,V");
  EXPECT_EQ(lines[1], s("GPVTG,303.60,T,,M,0.13,N,0.25,K,A")) << "no time field: unchanged";
  EXPECT_EQ(lines[2].substr(0, 17), "$GPGGA,000000.000");
  EXPECT_EQ(lines[3], s("GPGLL,5050.4122,N,00420.8265,E,000000.000,A,A", "\n")) << "LF kept";
  EXPECT_EQ(lines[4], s("GPZDA,000000.00,01,03,2024,00,00"));
  // No decimals: 23:59:59.9996 rounds to 00:00:00 too.
  EXPECT_EQ(lines[5], s("GPGST,000000,1.2,,,,0.9,0.8,1.9"));
  // Two decimals a second earlier: no rounding into the next day; the date is 29 February.
  const std::string before = retime_epoch(epoch, parse_iso8601_utc("2024-02-29T23:59:58.5Z"));
  EXPECT_NE(before.find("$GPZDA,235958.50,29,02,2024,00,00*"), std::string::npos) << before;
  EXPECT_NE(before.find(",290224,"), std::string::npos) << before;
}

TEST(ReplayLog, RetimeLeavesEmptyFieldsEmpty) {
  const std::string nofix = s("GPGGA,,,,,,0,,,,M,,M,,") + s("GPRMC,,V,,,,,,,,,,N");
  const ReplayLog log = parse_replay_log(nofix);
  ASSERT_EQ(log.epochs.size(), 1u);
  EXPECT_EQ(retime_epoch(log.epochs[0], parse_iso8601_utc("2024-05-01T12:00:00Z")), nofix);
}

TEST(ReplayLog, RetimeSendsAMalformedTimeFieldAsRecorded) {
  // Found by the nmea_log fuzz target: a malformed time field ("1.") was rewritten as a whole time
  // ("120000."), which pushed a long sentence over the parser's length limit; the retimed epoch then
  // lost a sentence. A malformed time stays as recorded; the good one beside it is retimed.
  const std::string body = "GPGGA,1.,4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,";
  const std::string bad = s(body + std::string(nmea::max_parse_chars - body.size() - 4, '9'));  // "$" "*hh": at the limit
  ASSERT_TRUE(nmea::parse_sentence(bad.substr(0, bad.size() - 2)).ok()) << bad;
  const ReplayLog log = parse_replay_log(gga("235951.004") + bad + s("GPGGA,235951.004.,03433942,N,,,1,,,,M,,M,,"));
  EXPECT_EQ(log.counts.bad_time_fields, 2u);
  std::string out;
  std::size_t sentences = 0;
  for (const LogEpoch& epoch : log.epochs) {
    out += retime_epoch(epoch, parse_iso8601_utc("2024-05-01T12:00:00Z"));
    sentences += epoch.sentences.size();
  }
  ASSERT_EQ(sentences, 3u);
  EXPECT_TRUE(checksums_ok(out)) << out;
  EXPECT_NE(out.find("$GPGGA,120000.000,"), std::string::npos) << out;
  EXPECT_NE(out.find(bad), std::string::npos) << out;
  EXPECT_NE(out.find("$GPGGA,235951.004.,03433942,N,"), std::string::npos) << out;
}

}  // namespace log_test
}  // namespace
}  // namespace gpsemu::replay
