// The garble fault on bytes: sentences and frames hit at the rate asked, each with a bad checksum
// or cut short, the rest untouched, deterministic from the seed.
#include "emulator/faults/garble.hpp"

#include <gtest/gtest.h>

#include <string>

#include "emulator/ubx/frame.hpp"
#include "nmea/parse.hpp"

namespace gpsemu::faults {
namespace {
namespace garble_test {

const std::string kEpoch =
    "$GPRMC,120000.00,A,4304.3500,N,08924.7500,W,0.000,0.00,010524,,,A*7D\r\n"
    "$GPGGA,120000.00,4304.3500,N,08924.7500,W,1,10,0.90,260.0,M,-33.9,M,,*65\r\n"
    "$GPGSA,A,3,01,02,03,04,05,06,07,08,09,10,,,1.50,0.90,1.20*0C\r\n";

/// An epoch of `n` copies of kEpoch plus one UBX frame each (NAV-CLOCK-like, 20 bytes of payload).
std::string epochs(int n) {
  std::string frame = {'\xB5', '\x62', '\x01', '\x22', '\x14', '\x00'};
  frame += std::string(20, '\x11');
  std::uint8_t a = 0, b = 0;
  for (std::size_t i = 2; i < frame.size(); ++i) {
    a = static_cast<std::uint8_t>(a + static_cast<std::uint8_t>(frame[i]));
    b = static_cast<std::uint8_t>(b + a);
  }
  frame += static_cast<char>(a);
  frame += static_cast<char>(b);
  std::string out;
  for (int i = 0; i < n; ++i) out += kEpoch + frame;
  return out;
}

/// Sentences with a valid checksum and whole UBX frames with a valid checksum in `bytes`.
std::pair<int, int> valid(const std::string& bytes) {
  int sentences = 0, frames = 0;
  nmea::StreamReader reader;
  sentences = static_cast<int>(reader.feed(bytes).size());
  ubx::FrameReader frames_reader;
  for (const auto& m : frames_reader.feed(bytes)) frames += std::holds_alternative<ubx::Frame>(m);
  return {sentences, frames};
}

TEST(Garble, RateZeroLeavesTheBytesAlone) {
  std::string bytes = epochs(5);
  const GarbleCounts c = garble(bytes, 0.0, 42);
  EXPECT_EQ(bytes, epochs(5));
  EXPECT_EQ(c.units, 20u);
  EXPECT_EQ(c.flipped + c.truncated, 0u);
}

TEST(Garble, RateOneBreaksEverySentenceAndFrame) {
  std::string bytes = epochs(50);
  const GarbleCounts c = garble(bytes, 1.0, 7);
  EXPECT_EQ(c.units, 200u);
  EXPECT_EQ(c.flipped + c.truncated, 200u);
  EXPECT_GT(c.flipped, 60u);    // about half each
  EXPECT_GT(c.truncated, 60u);
  const auto [sentences, frames] = valid(bytes);
  EXPECT_EQ(sentences, 0);
  EXPECT_EQ(frames, 0);
  EXPECT_LT(bytes.size(), epochs(50).size());  // the cut parts are gone
}

TEST(Garble, AboutTheRateOfUnitsIsHitAndTheOthersStayValid) {
  std::string bytes = epochs(500);  // 2000 units
  const GarbleCounts c = garble(bytes, 0.2, 99);
  const double hit = static_cast<double>(c.flipped + c.truncated) / static_cast<double>(c.units);
  EXPECT_NEAR(hit, 0.2, 0.03);
  const auto [sentences, frames] = valid(bytes);
  // Every unit not hit still parses (a cut sentence may swallow at most the next one's start: the
  // stream reader resynchronises at the next '$').
  EXPECT_GE(sentences + frames, static_cast<int>(c.units - c.flipped - c.truncated) - static_cast<int>(c.truncated));
  EXPECT_LE(sentences + frames, static_cast<int>(c.units - c.flipped - c.truncated));
}

TEST(Garble, TheSameSeedGivesTheSameBytesAnotherSeedOthers) {
  std::string a = epochs(20), b = epochs(20), c = epochs(20);
  (void)garble(a, 0.5, 1234);
  (void)garble(b, 0.5, 1234);
  (void)garble(c, 0.5, 1235);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(Garble, BytesOutsideSentencesAndFramesAreLeftAlone) {
  std::string bytes = "noise\r\n";
  const GarbleCounts c = garble(bytes, 1.0, 3);
  EXPECT_EQ(c.units, 0u);
  EXPECT_EQ(bytes, "noise\r\n");
}

}  // namespace garble_test
}  // namespace
}  // namespace gpsemu::faults
