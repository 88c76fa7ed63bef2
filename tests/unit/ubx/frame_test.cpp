// The UBX frame codec and the client stream reader: the checksum of a known frame (the CFG-MSG
// ArduPilot sends first), frames found among NMEA text and garbage whatever the chunking, bad
// checksums and absurd lengths counted and skipped, PUBX,40/41 parsed.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <string_view>

#include "emulator/ubx/frame.hpp"
#include "emulator/ubx/pubx.hpp"
#include "nmea/sentences.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace frame_test {

using test::unhex;

// ArduPilot's start-up blob: CFG-MSG NAV-SOL rate 1, then $PUBX,41 to 115200 baud.
const std::string ardupilot_blob =
    unhex("b562 0601 0300 010601 124f") + "$PUBX,41,1,0023,0001,115200,0*1C\r\n";

TEST(UbxFrame, ChecksumOfArduPilotsCfgMsgMatchesTheBytesItSends) {
  EXPECT_EQ(frame_bytes(msg::cfg_msg, unhex("010601")), unhex("b562 0601 0300 010601 124f"));
  EXPECT_EQ(fletcher_checksum(unhex("0601 0300 010601")), 0x4F12);
}

TEST(UbxFrame, EmptyPayloadFrameIsEightBytes) {
  EXPECT_EQ(frame_bytes(msg::mon_ver, ""), unhex("b562 0a04 0000 0e34"));
}

TEST(UbxFrameReader, FindsFramesAndPubxAmongGarbageInAnyChunking) {
  const std::string stream = std::string("junk\xB5") + ardupilot_blob + "$GPGGA,bad*00\r\n" +
                             frame_bytes(msg::cfg_rate, "") + std::string("\xB5\x62", 2) + "x";
  for (std::size_t chunk = 1; chunk <= stream.size(); ++chunk) {
    FrameReader reader;
    std::vector<ClientMessage> got;
    for (std::size_t at = 0; at < stream.size(); at += chunk) {
      for (ClientMessage& m : reader.feed(std::string_view(stream).substr(at, chunk))) got.push_back(std::move(m));
    }
    ASSERT_EQ(got.size(), 3u) << "chunk " << chunk;
    EXPECT_EQ(std::get<Frame>(got[0]), (Frame{msg::cfg_msg, unhex("010601")}));
    const auto pubx = parse_pubx41(std::get<nmea::Sentence>(got[1]));
    ASSERT_TRUE(pubx.has_value());
    EXPECT_EQ(pubx->port, Port::uart1);
    EXPECT_EQ(pubx->in_proto_mask, 0x23);
    EXPECT_EQ(pubx->out_proto_mask, 0x01);
    EXPECT_EQ(pubx->baud, 115200u);
    EXPECT_EQ(std::get<Frame>(got[2]), (Frame{msg::cfg_rate, ""}));
    EXPECT_EQ(reader.stats().frames_ok, 2u);
    EXPECT_EQ(reader.stats().sentences_ok, 1u);
    EXPECT_EQ(reader.stats().bad_sentences, 1u);
    EXPECT_EQ(reader.stats().garbage_bytes, 4u + 1u + 2u + 2u);  // "junk", lone 0xB5, 2 CR LF
  }
}

TEST(UbxFrameReader, BadChecksumIsCountedAndTheNextFrameStillFound) {
  std::string bad = frame_bytes(msg::cfg_rate, unhex("c8000100 0100"));
  bad.back() = static_cast<char>(bad.back() ^ 0x01);
  FrameReader reader;
  const auto got = reader.feed(bad + frame_bytes(msg::mon_ver, ""));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(std::get<Frame>(got[0]).id, msg::mon_ver);
  EXPECT_EQ(reader.stats().bad_checksum, 1u);
}

TEST(UbxFrameReader, TooLongLengthIsSkippedAndTheStreamRescanned) {
  // A header announcing 0xFFFF bytes, then a real frame right behind it.
  const std::string stream = unhex("b562 0601 ffff") + frame_bytes(msg::mon_ver, "");
  FrameReader reader;
  const auto got = reader.feed(stream);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(std::get<Frame>(got[0]).id, msg::mon_ver);
  EXPECT_EQ(reader.stats().too_long, 1u);
}

nmea::Sentence sentence_of_body(std::string_view body) {
  const auto s = nmea::parse_sentence(nmea::frame(body));
  EXPECT_TRUE(s.ok()) << body;
  return s.ok() ? *s : nmea::Sentence{};
}

TEST(UbxPubx, Pubx40SetsRatesPerPort) {
  const auto off = parse_pubx40(sentence_of_body("PUBX,40,GSV,0,0,0,0,0,0"));
  ASSERT_TRUE(off.has_value());
  EXPECT_EQ(off->message, "GSV");
  EXPECT_EQ(off->rates, (std::array<std::uint8_t, port_count>{0, 0, 0, 0, 0, 0}));
  const auto on = parse_pubx40(sentence_of_body("PUBX,40,ZDA,0,1,0,1,0,0"));
  ASSERT_TRUE(on.has_value());
  EXPECT_EQ(on->rates, (std::array<std::uint8_t, port_count>{0, 1, 0, 1, 0, 0}));
}

TEST(UbxPubx, MalformedCommandsAreRejected) {
  EXPECT_FALSE(parse_pubx40(sentence_of_body("PUBX,40,GSV,0,x,0,0,0,0")));
  EXPECT_FALSE(parse_pubx40(sentence_of_body("PUBX,40,GSV,0,0")));
  EXPECT_FALSE(parse_pubx40(sentence_of_body("PUBX,40,GSV,0,256,0,0,0,0")));
  EXPECT_FALSE(parse_pubx41(sentence_of_body("PUBX,41,1,0023,0001")));
  EXPECT_FALSE(parse_pubx41(sentence_of_body("PUBX,41,9,0023,0001,9600,0")));
  EXPECT_FALSE(parse_pubx41(sentence_of_body("PUBX,41,1,0023,0001,0,0")));
  EXPECT_FALSE(parse_pubx41(sentence_of_body("PUBX,40,GSV,0,0,0,0,0,0")));
  EXPECT_FALSE(parse_pubx40(sentence_of_body("GPGGA,1,2,3,4,5,6,7,8")));
}

}  // namespace frame_test
}  // namespace
}  // namespace gpsemu::ubx
