// RTCM3 corrections written to a u-blox port (PX4 and ArduPilot inject them through the GPS port):
// split from UBX and NMEA in any chunking, bad CRCs dropped and counted, handed to take_rtcm()
// without an ACK, reported by RXM-RTCM when the client turns it on (an F9P; an M8N has none), and
// NAV-PVT's lastCorrectionAge follows the fix's correction age.
#include <gtest/gtest.h>

#include <chrono>

#include "emulator/rtk/correction_age.hpp"
#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/nav.hpp"
#include "emulator/ubx/session.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace rtcm_input_test {

using namespace std::chrono;

const rtk::BasePosition kBase{77, 4198944.6, 174747.2, 4781886.9, 0.0};

std::string corrections() {
  std::string s;
  rtk::append_rtcm3_frame(s, rtk::encode_base_position(kBase, true));
  rtk::append_rtcm3_frame(s, rtk::encode_msm(1074, 77, 1000, 9, 2));
  rtk::append_rtcm3_frame(s, rtk::encode_msm(1084, 77, 1000, 7, 2));
  rtk::append_rtcm3_frame(s, rtk::encode_1230(77));
  return s;
}

TEST(UbxRtcmInput, FrameReaderSplitsRtcmFromUbxAndNmeaInAnyChunking) {
  const std::string stream = frame_bytes(msg::cfg_rate, "") + corrections() + "$PUBX,40,GLL,0,0,0,0,0,0*5C\r\n" +
                             std::string("\xD3\x7F") + frame_bytes(msg::mon_ver, "");
  for (std::size_t chunk = 1; chunk <= stream.size(); chunk += 7) {
    FrameReader reader;
    std::vector<ClientMessage> got;
    for (std::size_t at = 0; at < stream.size(); at += chunk) {
      for (ClientMessage& m : reader.feed(std::string_view(stream).substr(at, chunk))) got.push_back(std::move(m));
    }
    ASSERT_EQ(got.size(), 7u) << "chunk " << chunk;
    EXPECT_TRUE(std::holds_alternative<Frame>(got[0]));
    ASSERT_TRUE(std::holds_alternative<rtk::Rtcm3Frame>(got[1]));
    EXPECT_EQ(std::get<rtk::Rtcm3Frame>(got[1]).message_type(), 1006);
    EXPECT_EQ(std::get<rtk::Rtcm3Frame>(got[4]).message_type(), 1230);
    EXPECT_TRUE(std::holds_alternative<nmea::Sentence>(got[5]));
    EXPECT_TRUE(std::holds_alternative<Frame>(got[6]));
    EXPECT_EQ(reader.stats().rtcm_ok, 4u);
    EXPECT_EQ(reader.stats().frames_ok, 2u);
    EXPECT_EQ(reader.stats().garbage_bytes, 4u);  // CR LF, and the 0xD3 0x7F that is no frame
  }
}

TEST(UbxRtcmInput, ABadCrcIsDroppedAndCounted) {
  std::string bad = rtk::rtcm3_frame_bytes(rtk::encode_1230(5));
  bad[5] = static_cast<char>(bad[5] ^ 0x01);
  FrameReader reader;
  const auto got = reader.feed(bad + frame_bytes(msg::cfg_rate, ""));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_TRUE(std::holds_alternative<Frame>(got[0]));
  EXPECT_EQ(reader.stats().rtcm_bad_crc, 1u);
}

SessionSettings f9p() {
  SessionSettings s;
  s.start.model = ReceiverModel::ublox_f9p;
  return s;
}

TEST(UbxRtcmInput, SessionHandsTheMessagesOverWithoutAnAnswer) {
  Session session(f9p());
  session.client_wrote(corrections());
  EXPECT_TRUE(session.take_reply().empty());
  const std::vector<rtk::Rtcm3Message> got = session.take_rtcm();
  ASSERT_EQ(got.size(), 4u);
  ASSERT_TRUE(got[0].base.has_value());
  EXPECT_NEAR(got[0].base->ecef_x_m, kBase.ecef_x_m, 1e-4);
  EXPECT_EQ(got[1].msm->satellites, 9);
  EXPECT_EQ(got[2].msm->gnss, rtk::Gnss::glonass);
  EXPECT_TRUE(session.take_rtcm().empty());
  EXPECT_EQ(session.reader_stats().rtcm_ok, 4u);
}

TEST(UbxRtcmInput, RxmRtcmReportsEachMessageWhenTurnedOn) {
  Session session(f9p());
  session.client_wrote(frame_bytes(msg::cfg_msg, test::unhex("0232 01")));
  const auto acks = test::frames_in(session.take_reply());
  ASSERT_EQ(acks.size(), 1u);
  EXPECT_EQ(acks[0].id, msg::ack_ack);
  session.client_wrote(corrections());
  const auto reports = test::frames_in(session.take_reply());
  ASSERT_EQ(reports.size(), 4u);
  const std::array<std::uint16_t, 4> types{1006, 1074, 1084, 1230};
  for (std::size_t i = 0; i < reports.size(); ++i) {
    EXPECT_EQ(reports[i].id, msg::rxm_rtcm);
    ASSERT_EQ(reports[i].payload.size(), 8u);
    EXPECT_EQ(get_u1(reports[i].payload, 0), 2u);            // version
    EXPECT_EQ(get_u1(reports[i].payload, 1), 2u << 1);       // msgUsed: used, crcFailed 0
    EXPECT_EQ(get_u2(reports[i].payload, 4), 77u);           // refStation
    EXPECT_EQ(get_u2(reports[i].payload, 6), types[i]);      // msgType
  }
}

TEST(UbxRtcmInput, AnM8nHasNoRxmRtcm) {
  SessionSettings s;
  s.start.model = ReceiverModel::ublox_m8n;
  Session session(s);
  session.client_wrote(frame_bytes(msg::cfg_msg, test::unhex("0232 01")));
  (void)session.take_reply();
  session.client_wrote(corrections());
  EXPECT_TRUE(session.take_reply().empty());
  EXPECT_EQ(session.take_rtcm().size(), 4u);
}

TEST(UbxRtcmInput, LastCorrectionAgeCodes) {
  EXPECT_EQ(rtk::last_correction_age_code(std::nullopt), 0u);
  EXPECT_EQ(rtk::last_correction_age_code(0.5), 1u);
  EXPECT_EQ(rtk::last_correction_age_code(1.0), 2u);
  EXPECT_EQ(rtk::last_correction_age_code(4.9), 3u);
  EXPECT_EQ(rtk::last_correction_age_code(59.0), 9u);
  EXPECT_EQ(rtk::last_correction_age_code(500.0), 12u);
}

TEST(UbxRtcmInput, NavPvtCarriesCorrectionAgeAndCarrierSolution) {
  Session session(f9p());
  session.client_wrote(frame_bytes(msg::cfg_msg, test::unhex("0107 01")));
  (void)session.take_reply();
  nmea::Fix f;
  f.time_utc = sys_days{year{2026} / November / 24} + hours{12};
  f.quality = nmea::FixQuality::rtk_fixed;
  f.lat_deg = 47.0;
  f.lon_deg = 8.0;
  f.diff_age_s = 3.0;
  f.diff_station_id = 77;
  std::string out;
  session.append_solution(epoch_of(f), out);
  const auto frames = test::frames_in(out);
  const auto pvt = std::find_if(frames.begin(), frames.end(), [](const Frame& fr) { return fr.id == msg::nav_pvt; });
  ASSERT_NE(pvt, frames.end());
  EXPECT_EQ(get_u1(pvt->payload, 21) & 0x03u, 0x03u);  // gnssFixOK, diffSoln
  EXPECT_EQ(get_u1(pvt->payload, 21) >> 6, 2u);        // carrSoln fixed
  EXPECT_EQ((get_u2(pvt->payload, 78) >> 1) & 0x0Fu, 3u);  // lastCorrectionAge 2..5 s
}

// inProtoMask: a port whose input protocols exclude RTCM3 does not use the frames (no RTK, no
// RXM-RTCM), counts them ignored; the default has RTCM3 on, as a receiver's does.
TEST(UbxRtcmInput, RtcmInputOffOnThePortIgnoresTheFramesAndCountsThem) {
  constexpr std::uint32_t kUart1InprotRtcm3x = 0x10730004, kUsbInprotRtcm3x = 0x10770004;
  Session session(f9p());
  session.client_wrote(frame_bytes(msg::cfg_msg, test::unhex("0232 01")));  // RXM-RTCM on
  session.client_wrote(frame_bytes(msg::cfg_valset, test::valset({{kUart1InprotRtcm3x, 0}})));
  const auto acks = test::frames_in(session.take_reply());
  ASSERT_EQ(acks.size(), 2u);
  EXPECT_EQ(acks[1].id, msg::ack_ack);
  session.client_wrote(corrections());
  EXPECT_TRUE(session.take_reply().empty());  // no RXM-RTCM
  EXPECT_TRUE(session.take_rtcm().empty());
  EXPECT_EQ(session.stats().rtcm_ignored, 4u);
  EXPECT_EQ(session.reader_stats().rtcm_ok, 4u);  // whole frames, read and set aside
  // Another port's key changes nothing here; turning UART1's back on restores the input.
  session.client_wrote(frame_bytes(msg::cfg_valset, test::valset({{kUsbInprotRtcm3x, 1}})));
  session.client_wrote(corrections());
  EXPECT_TRUE(session.take_rtcm().empty());
  session.client_wrote(frame_bytes(msg::cfg_valset, test::valset({{kUart1InprotRtcm3x, 1}})));
  (void)session.take_reply();
  session.client_wrote(corrections());
  EXPECT_EQ(session.take_rtcm().size(), 4u);
  EXPECT_EQ(session.stats().rtcm_ignored, 8u);
}

TEST(UbxRtcmInput, AnM8CfgPrtWithoutBit5IgnoresRtcm3) {
  SessionSettings s;
  s.start.model = ReceiverModel::ublox_m8n;
  Session session(s);
  session.client_wrote(corrections());
  EXPECT_EQ(session.take_rtcm().size(), 4u);  // the default inProtoMask has RTCM3 (bit 5)
  // CFG-PRT UART1: 9600 8N1, inProtoMask UBX+NMEA (0x0003), outProtoMask UBX+NMEA.
  session.client_wrote(frame_bytes(msg::cfg_prt, test::unhex("01 00 0000 C0080000 80250000 0300 0300 0000 0000")));
  const auto acks = test::frames_in(session.take_reply());
  ASSERT_EQ(acks.size(), 1u);
  EXPECT_EQ(acks[0].id, msg::ack_ack);
  session.client_wrote(corrections());
  EXPECT_TRUE(session.take_rtcm().empty());
  EXPECT_EQ(session.stats().rtcm_ignored, 4u);
}

}  // namespace rtcm_input_test
}  // namespace
}  // namespace gpsemu::ubx
