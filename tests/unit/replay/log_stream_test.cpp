// The streaming log reader (emulator/replay/log_stream.hpp) on logs bigger than its look-ahead
// window: the epochs and their log times are those of the whole log, the window stays bounded,
// a CR LF split across two reads stays one line ending, untimed epochs before a first timed one
// far past the window are placed before it, the period is the median of the first spacings, and
// rewind() gives the same epochs again with the first pass's counts. Logs are generated here.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "emulator/replay/epoch_range.hpp"
#include "emulator/replay/log_stream.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::replay {
namespace {
namespace log_stream_test {

using namespace std::chrono;

std::string s(const std::string& body, const std::string& ending = "\r\n") {
  return fmt::format("${}*{:02X}{}", body, nmea::checksum(body), ending);
}

/// hhmmss.ss of `t` since midnight.
std::string hms(nanoseconds t) {
  const auto cs = duration_cast<milliseconds>(t).count() / 10;
  return fmt::format("{:02}{:02}{:02}.{:02}", cs / 360000 % 24, cs / 6000 % 60, cs / 100 % 60, cs % 100);
}

/// An epoch at `t`: GGA, RMC and two GSV (about 300 bytes).
std::string epoch(nanoseconds t) {
  return s(fmt::format("GPGGA,{},4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,", hms(t))) +
         s(fmt::format("GPRMC,{},A,4304.35012,N,08924.75027,W,0.000,,010524,,,A,V", hms(t))) +
         s("GPGSV,2,1,08,01,40,083,46,02,17,308,41,03,07,344,39,04,22,228,45") +
         s("GPGSV,2,2,08,05,40,083,46,06,17,308,41,07,07,344,39,08,22,228,45");
}

TEST(LogStream, ALogManyWindowsLongComesOutWholeOnItsTimelineWithTheWindowBounded) {
  const nanoseconds t0 = hours(23) + minutes(50);  // crosses midnight
  std::string text;
  constexpr int kEpochs = 12000;  // about 3.5 MB: a few windows
  for (int i = 0; i < kEpochs; ++i) text += epoch(t0 + i * milliseconds(100));
  LogStream stream(text, "test.nmea");
  EXPECT_EQ(stream.period(), milliseconds(100));
  EXPECT_EQ(stream.period_spacings(), kPeriodSpacings);
  std::string joined;
  std::size_t widest_window = 0;
  int i = 0;
  for (LogEpoch e; stream.pop(&e); ++i) {
    ASSERT_EQ(e.log_time, t0 + i * milliseconds(100)) << i;
    joined += e.bytes;
    std::size_t bytes = 0;
    for (const auto& w : stream.window()) bytes += w.bytes.size();
    widest_window = std::max(widest_window, bytes);
    ASSERT_LE(stream.window().size(), kLookAheadEpochs + kReadChunkBytes / 64) << i;
  }
  EXPECT_EQ(i, kEpochs);
  EXPECT_TRUE(joined == text);
  EXPECT_LE(widest_window, kLookAheadBytes + kReadChunkBytes + kMaxEpochBytes);
  EXPECT_TRUE(stream.ended());
  EXPECT_EQ(stream.epochs_read(), static_cast<std::uint64_t>(kEpochs));
  EXPECT_EQ(stream.counts().rollovers, 1u);
  EXPECT_EQ(stream.counts().gaps, 0u);
}

TEST(LogStream, ACrLfSplitBetweenTwoReadsStaysOneLineEnding) {
  const std::string first = s("GPGGA,120000.00,4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,");
  const std::string second = s("GPGGA,120001.00,4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,");
  // Comment lines so that the first sentence's CR is the last byte of the first read.
  std::string pad = "#";
  pad += std::string(kReadChunkBytes - first.size() - 1, 'x');
  pad += '\n';
  ASSERT_EQ(pad.size() + first.size() - 2, kReadChunkBytes - 1) << "the CR ends the first read, the LF starts the next";
  const std::string text = pad + first + second;
  LogStream stream(text, "test.nmea");
  LogEpoch a, b;
  ASSERT_TRUE(stream.pop(&a));
  ASSERT_TRUE(stream.pop(&b));
  EXPECT_EQ(a.bytes, first);
  EXPECT_EQ(b.bytes, second);
  EXPECT_FALSE(stream.pop());
  EXPECT_EQ(stream.counts().stream.comment_lines, 1u);
  EXPECT_EQ(stream.counts().stream.garbage_bytes, 0u);
}

TEST(LogStream, UntimedEpochsFarPastTheWindowArePlacedBeforeTheFirstTimedOne) {
  // A cold start: 1500 no-fix epochs without a time, then fixes at 10 Hz.
  const std::string nofix = s("GPGGA,,,,,,0,,,,M,,M,,") + s("GPRMC,,V,,,,,,,,,,N");
  std::string text;
  for (int i = 0; i < 1500; ++i) text += nofix;
  const nanoseconds t0 = hours(10);
  for (int i = 0; i < 400; ++i) text += epoch(t0 + i * milliseconds(100));
  LogStream stream(text, "test.nmea");
  EXPECT_EQ(stream.period(), milliseconds(100)) << "from the spacings past the window";
  EXPECT_EQ(stream.first_log_time(), t0 - 1500 * milliseconds(100));
  int i = 0;
  for (LogEpoch e; stream.pop(&e); ++i) ASSERT_EQ(e.log_time, t0 + (i - 1500) * milliseconds(100)) << i;
  EXPECT_EQ(i, 1900);
  EXPECT_EQ(stream.counts().untimed_epochs, 1500u);
}

TEST(LogStream, ThePeriodIsTheMedianOfTheFirstSpacings) {
  std::string text;
  nanoseconds t = hours(8);
  for (int i = 0; i < 400; ++i, t += seconds(1)) text += epoch(t);             // 1 Hz first
  for (int i = 0; i < 2000; ++i, t += milliseconds(100)) text += epoch(t);     // then 10 Hz
  LogStream stream(text, "test.nmea");
  EXPECT_EQ(stream.period(), seconds(1)) << "the first 256 spacings, not the whole log's median";
}

TEST(LogStream, RewindGivesTheSameEpochsWithTheFirstPassCounts) {
  std::string text = "# header\n";
  for (int i = 0; i < 5000; ++i) text += epoch(hours(12) + i * seconds(1));
  LogStream stream(text, "test.nmea");
  std::vector<nanoseconds> first, second;
  for (LogEpoch e; stream.pop(&e);) first.push_back(e.log_time);
  const LogCounts counts = stream.counts();
  stream.rewind();
  EXPECT_EQ(stream.position(), 0u);
  for (LogEpoch e; stream.pop(&e);) second.push_back(e.log_time);
  EXPECT_EQ(first, second);
  EXPECT_EQ(stream.counts().stream.comment_lines, counts.stream.comment_lines);
  EXPECT_EQ(stream.counts().stream.sentences_ok, 20000u);
  EXPECT_EQ(stream.epochs_read(), 5000u);
}

TEST(LogStream, ARangeIsFoundWhileStreaming) {
  std::string text;
  for (int i = 0; i < 6000; ++i) text += epoch(hours(12) + i * seconds(1));
  LogStream stream(text, "test.nmea");
  RangeCursor range(parse_log_position("from", "13:00:00"), parse_log_position("to", "13:00:02"),
                    stream.first_log_time());
  std::vector<std::uint64_t> in;
  for (const LogEpoch* e; (e = stream.peek()) != nullptr; (void)stream.pop()) {
    const auto place = range.place(stream.position(), *e);
    if (place == RangeCursor::Place::after) break;
    if (place == RangeCursor::Place::in) in.push_back(stream.position());
  }
  EXPECT_EQ(in, (std::vector<std::uint64_t>{3600, 3601, 3602}));
  EXPECT_EQ(range.first(), 3600u);
  EXPECT_FALSE(stream.ended()) << "read no further than the window past the range";
}

}  // namespace log_stream_test
}  // namespace
}  // namespace gpsemu::replay
