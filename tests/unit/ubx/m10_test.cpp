// `--receiver ublox-m10`: a u-blox M10 (MAX-M10S, SPG 5.10, protocol 34.10) as its interface
// description has it: MON-VER as the module answers (PX4 and ArduPilot detect an M10 by hwVersion
// 000A0000), configuration by CFG-VALSET/VALGET/VALDEL only (the legacy CFG-* messages NAKed, CFG-CFG
// and CFG-RST kept), no RTCM3 input (ignored; no RXM-RTCM), MON-RF but not MON-HW, 9600 baud.
#include <gtest/gtest.h>

#include <string>

#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/machine.hpp"
#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/ubx/messages.hpp"
#include "emulator/ubx/model.hpp"
#include "emulator/ubx/settings.hpp"
#include "emulator/ubx/session.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace m10_test {

using namespace std::chrono_literals;
using test::ack_of;
using test::effects_of;
using test::nak_of;
using test::send;
using test::unhex;
using test::valset;

ConfigMachine m10() {
  StartSettings start;
  start.model = ReceiverModel::ublox_m10;
  return ConfigMachine(start);
}

TEST(UbxM10, MonVerAnswersAsAMaxM10s) {
  ConfigMachine m = m10();
  const auto got = send(m, msg::mon_ver);
  ASSERT_EQ(got.frames.size(), 1u);
  const std::string& p = got.frames[0].payload;
  EXPECT_EQ(p.substr(0, 21), "ROM SPG 5.10 (7b202e)");
  EXPECT_EQ(p.substr(30, 8), "000A0000");
  EXPECT_NE(p.find("PROTVER=34.10"), std::string::npos);
  EXPECT_NE(p.find("MOD=MAX-M10S"), std::string::npos);
  EXPECT_EQ(receiver_model_from_name("ublox-m10"), ReceiverModel::ublox_m10);
  EXPECT_EQ(model_info(ReceiverModel::ublox_m10).default_baud, 9600u);
}

// The u-blox identity beside the receiver table agrees with its rows: MON-VER names the row's
// module and firmware, the NMEA the table says a model writes is exactly the u-blox NMEA messages
// (class 0xF0) gpsemu encodes, and a model takes RTCM3 when its corrections are not none.
TEST(UbxModels, TheIdentityOfEachModelAgreesWithItsRowOfTheReceiverTable) {
  for (std::size_t i = 0; i < kReceiverModels; ++i) {
    const auto model = static_cast<ReceiverModel>(i);
    const ReceiverFacts& f = facts_of(model);
    const ModelInfo& info = model_info(model);
    EXPECT_EQ(info.name, f.name);
    EXPECT_EQ(info.default_baud, f.default_baud);
    EXPECT_EQ(info.rtcm_input, f.corrections != Corrections::none) << f.name;
    const std::string ver = mon_ver_payload(model);
    EXPECT_NE(ver.find("FWVER=" + std::string(f.firmware)), std::string::npos) << f.name;
    if (model != ReceiverModel::generic) {
      EXPECT_NE(ver.find("MOD=" + std::string(f.module)), std::string::npos) << f.name;
    }
    for (const nmea::SentenceType t : nmea::all_sentence_types) {
      EXPECT_EQ(f.nmea_written.contains(t), nmea_message(t).has_value()) << f.name << " " << nmea::sentence_name(t);
    }
  }
}

TEST(UbxM10, LegacyCfgMessagesAreNakedAndValsetConfigures) {
  ConfigMachine m = m10();
  EXPECT_EQ(send(m, msg::cfg_rate, unhex("c800 0100 0100")).frames.front(), nak_of(msg::cfg_rate));
  EXPECT_EQ(send(m, msg::cfg_rate).frames.front(), nak_of(msg::cfg_rate));  // nor a poll
  EXPECT_EQ(send(m, msg::cfg_msg, unhex("0107 0001 0000 00")).frames.front(), nak_of(msg::cfg_msg));
  EXPECT_EQ(send(m, msg::cfg_prt, unhex("01")).frames.front(), nak_of(msg::cfg_prt));
  EXPECT_EQ(send(m, msg::cfg_nav5).frames.front(), nak_of(msg::cfg_nav5));
  EXPECT_EQ(send(m, {0x06, 0x31}, std::string(32, '\0')).frames.front(), nak_of({0x06, 0x31}));  // CFG-TP5
  EXPECT_EQ(m.settings().output_period(), 1000ms);

  const auto got = send(m, msg::cfg_valset, valset({{key::rate_meas, 200}}));
  ASSERT_EQ(got.frames.size(), 1u);
  EXPECT_EQ(got.frames[0], ack_of(msg::cfg_valset));
  const auto periods = effects_of<MeasurementPeriodChanged>(got.effects);
  ASSERT_EQ(periods.size(), 1u);
  EXPECT_EQ(periods[0].period, 200ms);
}

TEST(UbxM10, HasNoHighPrecisionOrTimeModeKeys) {
  // SPG 5.10 is standard-precision firmware: no CFG-NAVHPG (RTK) or CFG-TMODE (a base) group. A
  // VALSET or VALGET naming one is NAKed whole and changes nothing; an F9P takes them.
  constexpr std::uint32_t navhpg_dgnssmode = 0x20140011, tmode_mode = 0x20030001;
  ConfigMachine m = m10();
  EXPECT_EQ(send(m, msg::cfg_valset, valset({{navhpg_dgnssmode, 3}})).frames.front(), nak_of(msg::cfg_valset));
  EXPECT_NE(m.stats().last_nak.find("CFG-NAVHPG-DGNSSMODE (0x20140011): a key ublox-m10 lacks"), std::string::npos)
      << m.stats().last_nak;
  const auto both = send(m, msg::cfg_valset, valset({{key::rate_meas, 200}, {tmode_mode, 0}}));
  EXPECT_EQ(both.frames.front(), nak_of(msg::cfg_valset));
  EXPECT_EQ(m.settings().output_period(), 1000ms);
  EXPECT_EQ(send(m, msg::cfg_valget, unhex("0000 0000 11001420")).frames.front(), nak_of(msg::cfg_valget));
  EXPECT_FALSE(model_has_key_group(ReceiverModel::ublox_m10, navhpg_dgnssmode));
  EXPECT_TRUE(model_has_key_group(ReceiverModel::ublox_f9p, navhpg_dgnssmode));
  EXPECT_TRUE(model_has_key_group(ReceiverModel::ublox_m10, key::rate_meas));
}

TEST(UbxM10, HasMonRfButNeitherRxmRtcmNorMonHw) {
  ConfigMachine m = m10();
  const auto rf = send(m, msg::cfg_valset, valset({{*msgout_key(msg::mon_rf, Port::uart1), 1}}));
  EXPECT_EQ(rf.frames.front(), ack_of(msg::cfg_valset));
  for (const MessageId id : {msg::rxm_rtcm, msg::mon_hw, msg::nav_sol, msg::nav_hpposllh}) {
    const auto got = send(m, msg::cfg_valset, valset({{*msgout_key(id, Port::uart1), 1}}));
    EXPECT_EQ(got.frames.front(), nak_of(msg::cfg_valset)) << message_name(id);
  }
  // The summary names what the last NAK refused: here the key of a message the M10 lacks.
  EXPECT_EQ(m.stats().last_nak,
            "CFG-VALSET: CFG-MSGOUT-UBX_NAV_HPPOSLLH_UART1 (0x20910034): a message ublox-m10 lacks");
  (void)send(m, msg::cfg_rate);
  EXPECT_EQ(m.stats().last_nak, "CFG-RATE: a message ublox-m10 lacks");
  EXPECT_TRUE(model_has_message(ReceiverModel::ublox_m10, msg::nav_sig));
  EXPECT_TRUE(model_has_message(ReceiverModel::ublox_m10, msg::nav_sbas));  // documented again in SPG 5.10
}

TEST(UbxM10, IgnoresRtcm3ThoughItsInputKeyIsAcknowledged) {
  // PX4 writes CFG-UART1INPROT-RTCM3X = 1 to every generation-9 receiver and requires the ACK.
  SessionSettings settings;
  settings.start.model = ReceiverModel::ublox_m10;
  Session session(settings);
  EXPECT_EQ(session.machine().settings().ports[static_cast<std::size_t>(Port::uart1)].in_proto_mask & proto_rtcm3, 0);
  session.client_wrote(frame_bytes(msg::cfg_valset, valset({{0x10730004, 1}})));  // CFG-UART1INPROT-RTCM3X
  const auto acks = test::frames_in(session.take_reply());
  ASSERT_EQ(acks.size(), 1u);
  EXPECT_EQ(acks[0], ack_of(msg::cfg_valset));
  std::string corrections;
  rtk::append_rtcm3_frame(corrections, rtk::encode_1230(77));
  session.client_wrote(corrections);
  EXPECT_TRUE(session.take_rtcm().empty());
  EXPECT_TRUE(session.take_reply().empty());
  EXPECT_EQ(session.stats().rtcm_ignored, 1u);
}

}  // namespace m10_test
}  // namespace
}  // namespace gpsemu::ubx
