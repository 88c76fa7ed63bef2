// The configuration state machine, one message at a time: polls answered with the current
// configuration and ACK-ACK, writes applied with their effects, refused writes NAKed with nothing
// changed, the generation-9 key/value interface on an F9 and its refusal on an M8, MON-VER per
// model, CFG-RST, PUBX commands, and input that is no configuration at all.
#include <gtest/gtest.h>

#include <string>

#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/machine.hpp"
#include "nmea/sentences.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace machine_test {

using namespace std::chrono_literals;
using test::ack_of;
using test::effects_of;
using test::nak_of;
using test::send;
using test::unhex;

ConfigMachine machine_of(ReceiverModel model) {
  StartSettings start;
  start.model = model;
  return ConfigMachine(start);
}

TEST(UbxMachine, RatePollAnswersTheCurrentRateThenAck) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  const auto got = send(m, msg::cfg_rate);
  ASSERT_EQ(got.frames.size(), 2u);
  EXPECT_EQ(got.frames[0], (Frame{msg::cfg_rate, unhex("e803 0100 0100")}));
  EXPECT_EQ(got.frames[1], ack_of(msg::cfg_rate));
  EXPECT_TRUE(got.effects.empty());
}

TEST(UbxMachine, RateWriteChangesTheEpochPeriod) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  const auto got = send(m, msg::cfg_rate, unhex("6400 0100 0000"));  // 100 ms
  ASSERT_EQ(got.frames.size(), 1u);
  EXPECT_EQ(got.frames[0], ack_of(msg::cfg_rate));
  const auto periods = effects_of<MeasurementPeriodChanged>(got.effects);
  ASSERT_EQ(periods.size(), 1u);
  EXPECT_EQ(periods[0].period, 100ms);
  EXPECT_EQ(m.settings().output_period(), 100ms);
}

TEST(UbxMachine, ImpossibleRateIsNakedAndChangesNothing) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  for (const std::string& payload : {unhex("0a00 0100 0000"), unhex("6400 0000 0000"), unhex("6400 0100")}) {
    const auto got = send(m, msg::cfg_rate, payload);
    ASSERT_EQ(got.frames.size(), 1u);
    EXPECT_EQ(got.frames[0], nak_of(msg::cfg_rate));
    EXPECT_TRUE(got.effects.empty());
  }
  EXPECT_EQ(m.settings().output_period(), 1000ms);
}

TEST(UbxMachine, MessageRatePollAnswersEveryPortAndWriteTurnsMessagesOnAndOff) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  auto got = send(m, msg::cfg_msg, unhex("0107"));
  ASSERT_EQ(got.frames.size(), 2u);
  EXPECT_EQ(got.frames[0], (Frame{msg::cfg_msg, unhex("0107 000000000000")}));
  got = send(m, msg::cfg_msg, unhex("0107 01"));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_msg)});
  const auto rates = effects_of<MessageRateChanged>(got.effects);
  ASSERT_EQ(rates.size(), 1u);
  EXPECT_EQ(rates[0].id, msg::nav_pvt);
  EXPECT_EQ(rates[0].rate, 1);
  // NMEA GSV off on every port (8-byte form): the sentence effect for the client's port.
  got = send(m, msg::cfg_msg, unhex("f003 000000000000"));
  const auto sentences = effects_of<NmeaSentenceChanged>(got.effects);
  ASSERT_EQ(sentences.size(), 1u);
  EXPECT_EQ(sentences[0].type, nmea::SentenceType::gsv);
  EXPECT_FALSE(sentences[0].on);
}

TEST(UbxMachine, PortPollAndBaudChangeAfterTheAck) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  auto got = send(m, msg::cfg_prt);
  ASSERT_EQ(got.frames.size(), 2u);
  EXPECT_EQ(got.frames[0].payload, unhex("01 00 0000 d0080000 80250000 2300 0300 0000 0000"));  // 9600
  std::string prt = got.frames[0].payload;
  prt.replace(8, 4, unhex("00c20100"));  // 115200
  prt.replace(14, 2, unhex("0100"));    // UBX out only
  got = send(m, msg::cfg_prt, prt);
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_prt)});
  const auto bauds = effects_of<BaudChanged>(got.effects);
  ASSERT_EQ(bauds.size(), 1u);
  EXPECT_EQ(bauds[0].baud, 115200u);
  const auto protocols = effects_of<OutputProtocolsChanged>(got.effects);
  ASSERT_EQ(protocols.size(), 1u);
  EXPECT_TRUE(protocols[0].ubx);
  EXPECT_FALSE(protocols[0].nmea);
  prt.replace(8, 4, unhex("39300000"));  // 12345 baud: refused
  EXPECT_EQ(send(m, msg::cfg_prt, prt).frames, std::vector<Frame>{nak_of(msg::cfg_prt)});
}

TEST(UbxMachine, Nav5WriteChangesOnlyTheMaskedGroups) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  std::string nav5(36, '\0');
  nav5[0] = 0x01;  // mask: dynamic model only
  nav5[2] = 8;     // airborne < 4 g
  nav5[3] = 0;     // fixMode 0 would be refused, but its group is not selected
  EXPECT_EQ(send(m, msg::cfg_nav5, nav5).frames, std::vector<Frame>{ack_of(msg::cfg_nav5)});
  EXPECT_EQ(m.settings().dyn_model(), 8);
  EXPECT_EQ(m.settings().nav5[3], 3);
  nav5[0] = 0x01;
  nav5[2] = 1;  // no such model
  EXPECT_EQ(send(m, msg::cfg_nav5, nav5).frames, std::vector<Frame>{nak_of(msg::cfg_nav5)});
  const auto polled = send(m, msg::cfg_nav5);
  ASSERT_EQ(polled.frames.size(), 2u);
  EXPECT_EQ(polled.frames[0].payload.size(), 36u);
  EXPECT_EQ(polled.frames[0].payload[2], 8);
}

TEST(UbxMachine, GnssAndSbasPollsAnswerAndWritesAreKept) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  const auto gnss = send(m, msg::cfg_gnss);
  ASSERT_EQ(gnss.frames.size(), 2u);
  EXPECT_EQ(gnss.frames[0].payload.size(), 4u + 7 * 8);
  std::string sbas = send(m, msg::cfg_sbas).frames.at(0).payload;
  sbas[0] = 0;  // SBAS off
  EXPECT_EQ(send(m, msg::cfg_sbas, sbas).frames, std::vector<Frame>{ack_of(msg::cfg_sbas)});
  EXPECT_EQ(send(m, msg::cfg_sbas).frames.at(0).payload, sbas);
}

TEST(UbxMachine, MonVerMatchesTheModel) {
  ConfigMachine m8 = machine_of(ReceiverModel::ublox_m8n);
  const Frame m8_ver = send(m8, msg::mon_ver).frames.at(0);
  EXPECT_EQ(m8_ver.payload.substr(30, 8), "00080000");
  EXPECT_NE(m8_ver.payload.find("PROTVER=18.00"), std::string::npos);
  ConfigMachine f9 = machine_of(ReceiverModel::ublox_f9p);
  const Frame f9_ver = send(f9, msg::mon_ver).frames.at(0);
  EXPECT_EQ(f9_ver.payload.substr(30, 8), "00190000");
  EXPECT_NE(f9_ver.payload.find("MOD=ZED-F9P"), std::string::npos);
  EXPECT_EQ((f9_ver.payload.size() - 40) % 30, 0u);
}

TEST(UbxMachine, M8RefusesTheKeyValueInterface) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  EXPECT_EQ(send(m, msg::cfg_valset, test::valset({{key::rate_meas, 100}})).frames,
            std::vector<Frame>{nak_of(msg::cfg_valset)});
  EXPECT_EQ(send(m, msg::cfg_valget, test::valget({key::rate_meas})).frames,
            std::vector<Frame>{nak_of(msg::cfg_valget)});
  EXPECT_EQ(m.settings().output_period(), 1000ms);
}

TEST(UbxMachine, F9ValsetThenValgetReadsTheValuesBack) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_f9p);
  auto got = send(m, msg::cfg_valset,
                  test::valset({{key::rate_meas, 200}, {key::navspg_dynmodel, 4}, {key::msgout_nav_pvt_i2c + 1, 1},
                                {key::msgout_nmea_gga_i2c + 1, 0}, {0x10F60051, 1}}));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
  EXPECT_EQ(effects_of<MeasurementPeriodChanged>(got.effects).at(0).period, 200ms);
  EXPECT_EQ(effects_of<MessageRateChanged>(got.effects).at(0).id, msg::nav_pvt);
  EXPECT_FALSE(effects_of<NmeaSentenceChanged>(got.effects).at(0).on);
  got = send(m, msg::cfg_valget, test::valget({key::rate_meas, key::navspg_dynmodel, 0x10F60051, 0x20030001}));
  ASSERT_EQ(got.frames.size(), 2u);
  EXPECT_EQ(got.frames[0].id, msg::cfg_valget);
  EXPECT_EQ(got.frames[0].payload, unhex("01 00 0000 01002130 c800 21001120 04 5100f610 01 01000320 00"));
  EXPECT_EQ(got.frames[1], ack_of(msg::cfg_valget));
  // The factory default layer still has 1 Hz.
  got = send(m, msg::cfg_valget, test::valget({key::rate_meas}, 7));
  EXPECT_EQ(got.frames.at(0).payload, unhex("01 07 0000 01002130 e803"));
}

TEST(UbxMachine, ValsetWithOneBadValueChangesNothing) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_f9p);
  const auto got = send(m, msg::cfg_valset, test::valset({{key::rate_meas, 100}, {key::uart1_baudrate, 1234}}));
  EXPECT_EQ(got.frames, std::vector<Frame>{nak_of(msg::cfg_valset)});
  EXPECT_TRUE(got.effects.empty());
  EXPECT_EQ(m.settings().output_period(), 1000ms);
  std::string truncated = test::valset({{key::rate_meas, 100}});
  truncated.pop_back();
  EXPECT_EQ(send(m, msg::cfg_valset, truncated).frames, std::vector<Frame>{nak_of(msg::cfg_valset)});
}

TEST(UbxMachine, ValsetToFlashOnlyIsAckedWithoutEffect) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_f9p);
  const auto got = send(m, msg::cfg_valset, test::valset({{key::rate_meas, 100}}, 0x04));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
  EXPECT_TRUE(got.effects.empty());
}

TEST(UbxMachine, UnknownKeyValgetIsNaked) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_f9p);
  EXPECT_EQ(send(m, msg::cfg_valget, test::valget({0x20FF0001})).frames, std::vector<Frame>{nak_of(msg::cfg_valget)});
}

TEST(UbxMachine, ColdResetIsNotAnsweredButStartsCold) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  const auto got = send(m, msg::cfg_rst, unhex("ffff 02 00"));
  EXPECT_TRUE(got.frames.empty());
  EXPECT_EQ(effects_of<ColdStart>(got.effects).size(), 1u);
  EXPECT_TRUE(send(m, msg::cfg_rst, unhex("0000 02 00")).effects.empty());  // hot start
}

TEST(UbxMachine, SaveAndLoadDefaultsAreAcked) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  (void)send(m, msg::cfg_rate, unhex("c800 0100 0000"));
  EXPECT_EQ(send(m, msg::cfg_cfg, unhex("00000000 ffffffff 00000000")).frames, std::vector<Frame>{ack_of(msg::cfg_cfg)});
  EXPECT_EQ(m.settings().output_period(), std::chrono::milliseconds{200});
  const auto got = send(m, msg::cfg_cfg, unhex("ffffffff 00000000 ffffffff 17"));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_cfg)});
  EXPECT_EQ(m.settings().output_period(), 1000ms);
  EXPECT_EQ(effects_of<MeasurementPeriodChanged>(got.effects).at(0).period, 1000ms);
}

TEST(UbxMachine, NavPollIsAnsweredWithTheNextSolution) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  const auto got = send(m, msg::nav_pvt);
  EXPECT_TRUE(got.frames.empty());
  EXPECT_EQ(effects_of<PollOnce>(got.effects).at(0).id, msg::nav_pvt);
}

TEST(UbxMachine, PubxCommandsChangeSentencesAndBaudWithoutAnswer) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  Answer a = m.feed(nmea::frame("PUBX,40,GLL,0,0,0,0,0,0"));
  EXPECT_TRUE(a.bytes.empty());
  ASSERT_EQ(test::effects_of<NmeaSentenceChanged>(a.effects).size(), 1u);
  EXPECT_EQ(test::effects_of<NmeaSentenceChanged>(a.effects)[0].type, nmea::SentenceType::gll);
  a = m.feed(nmea::frame("PUBX,41,1,0007,0003,38400,0"));
  EXPECT_TRUE(a.bytes.empty());
  EXPECT_EQ(test::effects_of<BaudChanged>(a.effects).at(0).baud, 38400u);
}

TEST(UbxMachine, GarbageAndForeignMessagesAreIgnored) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  Answer a = m.feed(std::string("\x00\xff$GPGGA,1*00\r\n\xB5\x62\x01", 18) + frame_bytes({0x0D, 0x01}, "xyz") +
                    nmea::frame("GPTXT,01,01,02,hello"));
  EXPECT_TRUE(a.bytes.empty());
  EXPECT_TRUE(a.effects.empty());
  EXPECT_EQ(m.stats().ignored, 2u);
}

// The table of docs/ublox.md: CFG-MSG of each gated message is ACKed by the models that have it
// and NAKed by the others; a poll of it is answered (with the next solution) only where it exists.
TEST(UbxMachine, EachModelHasItsMessagesAndNaksTheOthers) {
  using M = ReceiverModel;
  struct Row {
    MessageId id;
    bool m8n, m9n, f9p;
  };
  const Row rows[] = {{msg::nav_svinfo, true, false, false},   {msg::nav_sbas, true, false, false},
                      {msg::nav_sig, false, true, true},       {msg::mon_rf, false, true, true},
                      {msg::nav_hpposllh, false, false, true}, {msg::nav_relposned, false, false, true},
                      {msg::mon_hw, true, true, true},         {msg::nav_clock, true, true, true},
                      {msg::nav_sat, true, true, true},        {msg::nav_timels, true, true, true}};
  for (const Row& r : rows) {
    for (const auto& [model, has] : {std::pair{M::ublox_m8n, r.m8n}, std::pair{M::ublox_m9n, r.m9n},
                                     std::pair{M::ublox_f9p, r.f9p}, std::pair{M::generic, r.m8n}}) {
      ConfigMachine m = machine_of(model);
      const std::string on{char(r.id.msg_class), char(r.id.msg_id), char(1)};
      EXPECT_EQ(send(m, msg::cfg_msg, on).frames, std::vector<Frame>{has ? ack_of(msg::cfg_msg) : nak_of(msg::cfg_msg)})
          << model_info(model).name << " " << int(r.id.msg_class) << "/" << int(r.id.msg_id);
      EXPECT_EQ(m.settings().rate(r.id, Port::uart1), has ? 1 : 0);
      const auto poll = send(m, r.id);
      EXPECT_TRUE(poll.frames.empty());
      const bool encoded = r.id != msg::nav_sbas;  // NAV-RELPOSNED is encoded (a moving-base rover's)
      EXPECT_EQ(effects_of<PollOnce>(poll.effects).size(), has && encoded ? 1u : 0u) << model_info(model).name;
    }
  }
}

}  // namespace machine_test
}  // namespace
}  // namespace gpsemu::ubx
