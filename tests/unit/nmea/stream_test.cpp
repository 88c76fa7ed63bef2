// StreamReader over a receiver's raw byte stream: NMEA interleaved with UBX and CASIC binary
// frames (one containing '$'), gpsd comment lines, empty lines, CR LF / LF / CR endings, a bad
// checksum, a sentence without checksum, an overlong line; exact counters and sentences whatever
// the chunking.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "nmea/parse.hpp"

namespace gpsemu::nmea {
namespace {
namespace stream_test {

const std::string gga = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47";
const std::string rmc = "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A";
const std::string rmc41 = "$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A,V*2D";
const std::string no_fix = "$GPGGA,,,,,,0,00,99.99,,,,,,*48";

std::string bytes(std::initializer_list<int> values) {
  std::string out;
  for (int v : values) out += static_cast<char>(v);
  return out;
}

// A mixed log. Expected: 4 sentences (gga, rmc, rmc41, no_fix at finish), 1 bad checksum,
// 3 malformed, 2 comments, 12 + 6 + 21 + 10 + 40 = 89 garbage bytes.
std::string mixed_stream() {
  std::string s;
  s += "# gpsd log: u-blox M8, 9600 baud\n";  // comment 1
  s += "\n";
  s += bytes({0xB5, 0x62, 0x01, 0x07, 0x04, 0x00, '$', 0x01, 0x02, 0x03, 0xAA, 0xBB});  // 12 garbage
  s += gga + "\r\n";                                                 // ok 1
  s += bytes({0xBA, 0xCE, 0x04, 0x00}) + "$xy,1" + bytes({0x00, 0x05});  // 6 garbage, malformed 1
  s += rmc + "\n";                                                   // ok 2, LF only
  s += gga.substr(0, gga.size() - 2) + "48\r\n";                     // bad checksum
  s += "$GPGGA,123519\r\n";                                          // malformed 2: no checksum
  s += "#comment two\r\n";                                           // comment 2
  s += "hello # not a comment\n";                                    // 21 garbage
  s += bytes({0xB5, 0x62, 0x05, 0x01, 0x02, 0x00, 0x06, 0x01, 0x0F, 0x38});  // 10 garbage (UBX ACK)
  s += rmc41 + "\r\n";                                               // ok 3, right after binary
  s += "$GPTXT," + std::string(150, 'A') + "*00\r\n";                // malformed 3, 160-120 garbage
  s += "\r\n\r\n";
  s += no_fix;  // ok 4, no final line end: returned by finish()
  return s;
}

struct Outcome {
  std::vector<std::string> types;  // talker + type + first field of every sentence, in order
  StreamStats stats;
};

Outcome read_in_chunks(const std::string& stream, const std::vector<std::size_t>& cuts) {
  StreamReader reader;
  Outcome out;
  auto keep = [&out](const Sentence& s) {
    out.types.push_back(s.talker + s.type + "," + (s.fields.empty() ? "" : s.fields[0]));
  };
  std::size_t begin = 0;
  for (std::size_t cut : cuts) {
    for (const Sentence& s : reader.feed(std::string_view(stream).substr(begin, cut - begin))) keep(s);
    begin = cut;
  }
  for (const Sentence& s : reader.feed(std::string_view(stream).substr(begin))) keep(s);
  if (const auto last = reader.finish()) keep(*last);
  out.stats = reader.stats();
  return out;
}

void expect_mixed_outcome(const Outcome& out, const std::string& how) {
  EXPECT_EQ(out.types, (std::vector<std::string>{"GPGGA,123519", "GPRMC,123519", "GPRMC,083559.00", "GPGGA,"}))
      << how;
  EXPECT_EQ(out.stats.sentences_ok, 4u) << how;
  EXPECT_EQ(out.stats.bad_checksum, 1u) << how;
  EXPECT_EQ(out.stats.malformed, 3u) << how;
  EXPECT_EQ(out.stats.garbage_bytes, 89u) << how;
  EXPECT_EQ(out.stats.comment_lines, 2u) << how;
}

TEST(NmeaStreamReader, MixedStreamInOneFeed) { expect_mixed_outcome(read_in_chunks(mixed_stream(), {}), "one feed"); }

TEST(NmeaStreamReader, MixedStreamSplitInsideBinaryDollarAndInsideASentence) {
  const std::string s = mixed_stream();
  const std::size_t dollar_in_ubx = s.find('$');  // the '$' inside the first UBX frame
  const std::size_t mid_rmc = s.find(rmc) + 30;
  ASSERT_EQ(static_cast<unsigned char>(s[dollar_in_ubx - 1]), 0x00);
  expect_mixed_outcome(read_in_chunks(s, {dollar_in_ubx + 1, mid_rmc}), "two cuts");
}

TEST(NmeaStreamReader, MixedStreamSameAtEverySplitPointAndByteByByte) {
  const std::string s = mixed_stream();
  for (std::size_t cut = 0; cut <= s.size(); ++cut) {
    expect_mixed_outcome(read_in_chunks(s, {cut}), "cut at " + std::to_string(cut));
  }
  std::vector<std::size_t> every_byte;
  for (std::size_t i = 1; i < s.size(); ++i) every_byte.push_back(i);
  expect_mixed_outcome(read_in_chunks(s, every_byte), "byte by byte");
}

TEST(NmeaStreamReader, CrOnlyEndingsAndDollarCuttingASentence) {
  const Outcome out = read_in_chunks(gga + "\r" + rmc + "\r" + "$GPGGA,1234" + gga + "\r", {});
  EXPECT_EQ(out.types, (std::vector<std::string>{"GPGGA,123519", "GPRMC,123519", "GPGGA,123519"}));
  EXPECT_EQ(out.stats.malformed, 1u);  // "$GPGGA,1234" had a ',' before the next '$'
  EXPECT_EQ(out.stats.garbage_bytes, 0u);
}

TEST(NmeaStreamReader, HashFollowedByBinaryIsGarbageNotAComment) {
  const Outcome out = read_in_chunks("#" + bytes({0xB5, 0x62}) + gga + "\r\n", {});
  EXPECT_EQ(out.types, (std::vector<std::string>{"GPGGA,123519"}));
  EXPECT_EQ(out.stats.comment_lines, 0u);
  EXPECT_EQ(out.stats.garbage_bytes, 3u);
}

TEST(NmeaStreamReader, DollarWithoutLineEndIsAbandonedAfter120Bytes) {
  // 10 000 printable bytes after a '$' and no line end: one malformed, the rest garbage, and the
  // next line is read normally.
  const Outcome out = read_in_chunks("$" + std::string(10'000, 'x') + "\n" + gga + "\n", {5000});
  EXPECT_EQ(out.types, (std::vector<std::string>{"GPGGA,123519"}));
  EXPECT_EQ(out.stats.malformed, 1u);
  EXPECT_EQ(out.stats.garbage_bytes, 10'001u - max_parse_chars);
}

TEST(NmeaStreamReader, FinishCountsAPendingComment) {
  StreamReader reader;
  EXPECT_TRUE(reader.feed("# last line without newline").empty());
  EXPECT_FALSE(reader.finish().has_value());
  EXPECT_EQ(reader.stats().comment_lines, 1u);
  EXPECT_EQ(reader.stats().garbage_bytes, 0u);
}

}  // namespace stream_test
}  // namespace
}  // namespace gpsemu::nmea
