// RTCM3 framing: CRC-24Q, frames split from a stream in any chunking, bad CRC and garbage counted,
// and the message fields (1005/1006, MSM, 1230, 4072) decoded from real and encoded frames.
#include "emulator/rtk/rtcm3_reader.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "emulator/rtk/rtcm3_messages.hpp"

namespace gpsemu::rtk {
namespace {
namespace rtcm3_reader_test {

std::string hex_bytes(std::initializer_list<int> values) {
  std::string out;
  for (const int v : values) out.push_back(static_cast<char>(v));
  return out;
}

// The example 1005 frame of RTCM 10403.3 (station 2003, ARP X 1114104.5999, Y -4850729.7108,
// Z 3975521.4643 m): as a receiver sends it, CRC included.
const std::string kStandard1005 = hex_bytes({0xD3, 0x00, 0x13, 0x3E, 0xD7, 0xD3, 0x02, 0x02, 0x98, 0x0E, 0xDE, 0xEF,
                                             0x34, 0xB4, 0xBD, 0x62, 0xAC, 0x09, 0x41, 0x98, 0x6F, 0x33, 0x36, 0x0B,
                                             0x98});

TEST(Crc24q, MatchesTheStandardsExampleFrame) {
  const std::string body = kStandard1005.substr(0, kStandard1005.size() - 3);
  EXPECT_EQ(crc24q(body), 0x360B98u);
  EXPECT_EQ(rtcm3_frame_bytes(body.substr(3)), kStandard1005);
}

TEST(Crc24q, OfNothingIsZeroAndOfOneByteIsItsTableEntry) {
  EXPECT_EQ(crc24q(""), 0u);
  EXPECT_NE(crc24q(std::string(1, '\x01')), 0u);
  EXPECT_NE(crc24q("a"), crc24q("b"));
}

TEST(Rtcm3Decode, TheStandardsExample1005) {
  Rtcm3Reader reader;
  const std::vector<Rtcm3Frame> frames = reader.feed(kStandard1005);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].message_type(), 1005);
  const Rtcm3Message m = decode_rtcm3(frames[0].payload);
  ASSERT_TRUE(m.base.has_value());
  EXPECT_TRUE(m.valid);
  EXPECT_EQ(m.station_id, 2003);
  EXPECT_NEAR(m.base->ecef_x_m, 1114104.5999, 1e-6);
  EXPECT_NEAR(m.base->ecef_y_m, -4850729.7108, 1e-6);
  EXPECT_NEAR(m.base->ecef_z_m, 3975521.4643, 1e-6);
  EXPECT_EQ(describe(m), "1005 base position");
}

TEST(Rtcm3Reader, SplitsFramesInEveryChunkingAndCountsGarbage) {
  BasePosition base{4095, 4198944.6, 174747.2, 4781886.9, 1.5};
  std::string stream = "xx";
  append_rtcm3_frame(stream, encode_base_position(base, true));
  stream += "\x01\x02\x03";
  append_rtcm3_frame(stream, encode_msm(1077, 4095, 123456789, 9, 2));
  append_rtcm3_frame(stream, encode_1230(4095));
  for (std::size_t chunk = 1; chunk <= stream.size(); ++chunk) {
    Rtcm3Reader reader;
    std::vector<Rtcm3Frame> got;
    for (std::size_t at = 0; at < stream.size(); at += chunk) {
      for (Rtcm3Frame& f : reader.feed(std::string_view(stream).substr(at, chunk))) got.push_back(std::move(f));
    }
    ASSERT_EQ(got.size(), 3u) << "chunk " << chunk;
    EXPECT_EQ(got[0].message_type(), 1006);
    EXPECT_EQ(got[1].message_type(), 1077);
    EXPECT_EQ(got[2].message_type(), 1230);
    EXPECT_EQ(reader.stats().frames_ok, 3u);
    EXPECT_EQ(reader.stats().garbage_bytes, 5u);
    EXPECT_EQ(reader.stats().by_type[1077], 1u);
  }
}

TEST(Rtcm3Reader, DropsAndCountsAFrameWithABadCrcAndGoesOn) {
  std::string bad = rtcm3_frame_bytes(encode_1230(7));
  bad[4] = static_cast<char>(bad[4] ^ 0x10);
  Rtcm3Reader reader;
  const std::vector<Rtcm3Frame> frames = reader.feed(bad + rtcm3_frame_bytes(encode_1230(8)));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(decode_rtcm3(frames[0].payload).station_id, 8);
  EXPECT_EQ(reader.stats().bad_crc, 1u);
  EXPECT_EQ(reader.stats().frames_ok, 1u);
}

TEST(Rtcm3Reader, APreambleWithReservedBitsSetIsGarbageAndTheNextByteMayStartAFrame) {
  Rtcm3Reader reader;
  const std::vector<Rtcm3Frame> frames = reader.feed("\xD3\xFF" + std::string("\xD3") + rtcm3_frame_bytes(encode_1230(9)));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(reader.stats().garbage_bytes, 3u);  // D3, FF, the second D3 (followed by D3: reserved bits set)
}

TEST(Rtcm3Framer, ReportsEachStepOfAFrame) {
  const std::string frame = rtcm3_frame_bytes("\x3E\xD0");
  Rtcm3Framer framer;
  for (std::size_t i = 0; i + 1 < frame.size(); ++i) {
    EXPECT_EQ(framer.push(static_cast<std::uint8_t>(frame[i])), Rtcm3Framer::Step::more);
  }
  EXPECT_EQ(framer.push(static_cast<std::uint8_t>(frame.back())), Rtcm3Framer::Step::frame);
  EXPECT_EQ(framer.take().payload, std::string("\x3E\xD0"));
  EXPECT_EQ(framer.pending_bytes(), 0u);
  EXPECT_EQ(framer.push(rtcm3_preamble), Rtcm3Framer::Step::more);
  EXPECT_EQ(framer.push(0x04), Rtcm3Framer::Step::not_rtcm);
}

TEST(Rtcm3Decode, Base1006RoundTripsToATenthOfAMillimetre) {
  const BasePosition base{1234, 4198944.6012, -174747.2347, 4781886.9001, 2.0345};
  const Rtcm3Message m = decode_rtcm3(encode_base_position(base, true));
  ASSERT_TRUE(m.base.has_value());
  EXPECT_TRUE(m.valid);
  EXPECT_EQ(m.type, 1006);
  EXPECT_EQ(m.base->station_id, 1234);
  EXPECT_NEAR(m.base->ecef_x_m, base.ecef_x_m, 1e-4);
  EXPECT_NEAR(m.base->ecef_y_m, base.ecef_y_m, 1e-4);
  EXPECT_NEAR(m.base->ecef_z_m, base.ecef_z_m, 1e-4);
  EXPECT_NEAR(m.base->antenna_height_m, 2.0345, 1e-4);
}

TEST(Rtcm3Decode, MsmHeadersOfEachGnssAndTheirCounts) {
  struct Case {
    std::uint16_t type;
    Gnss gnss;
    int msm;
  };
  for (const Case c : {Case{1074, Gnss::gps, 4}, Case{1084, Gnss::glonass, 4}, Case{1094, Gnss::galileo, 4},
                       Case{1124, Gnss::beidou, 4}, Case{1077, Gnss::gps, 7}, Case{1087, Gnss::glonass, 7},
                       Case{1097, Gnss::galileo, 7}, Case{1127, Gnss::beidou, 7}, Case{1117, Gnss::qzss, 7}}) {
    const Rtcm3Message m = decode_rtcm3(encode_msm(c.type, 17, 345600000, 10, 2));
    ASSERT_TRUE(m.msm.has_value()) << c.type;
    EXPECT_TRUE(m.valid) << c.type;
    EXPECT_EQ(m.station_id, 17);
    EXPECT_EQ(m.msm->gnss, c.gnss);
    EXPECT_EQ(m.msm->msm, c.msm);
    EXPECT_EQ(m.msm->epoch_time, 345600000u);
    EXPECT_EQ(m.msm->satellites, 10);
    EXPECT_EQ(m.msm->signals, 2);
    EXPECT_EQ(m.msm->cells, 20);
  }
}

TEST(Rtcm3Decode, AnMsmShorterThanItsMasksAnnounceIsNotValid) {
  std::string msm = encode_msm(1077, 3, 0, 8, 2);
  msm.resize(msm.size() - 10);
  EXPECT_FALSE(decode_rtcm3(msm).valid);
  EXPECT_FALSE(decode_rtcm3(encode_base_position({}, false).substr(0, 8)).valid);
}

TEST(Rtcm3Decode, OtherTypesKeepTheirNumber) {
  BitWriter w;
  w.u(4072, 12);
  w.u(0, 12);
  const Rtcm3Message u = decode_rtcm3(w.bytes());
  EXPECT_EQ(u.subtype, 0);
  EXPECT_EQ(describe(u), "4072.0 u-blox");
  BitWriter e;
  e.u(1019, 12);
  e.u(5, 12);
  EXPECT_EQ(describe(decode_rtcm3(e.bytes())), "1019 other");
  EXPECT_EQ(describe(decode_rtcm3(encode_1230(1))), "1230 GLONASS biases");
}

}  // namespace rtcm3_reader_test
}  // namespace
}  // namespace gpsemu::rtk
