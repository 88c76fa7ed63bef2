// One u-blox port end to end, pure: an F9P told by a client to write NAV-PVT at 5 Hz with NMEA
// off answers at once (before any epoch), then writes only NAV-PVT frames on the 200 ms grid of
// a 10 Hz epoch stream; polls are answered with the next solution; a baud change and a cold
// reset reach the caller as effects; NAV-STATUS counts time to first fix; an epoch is its NAV
// messages, its NMEA sentences, then NAV-EOE. Each model writes and answers the messages it has
// (M8: NAV-SVINFO, MON-HW; M9/F9: NAV-SIG, MON-RF; F9: NAV-HPPOSLLH) and NAKs the others; a cold
// reset starts the receiver's run time again.
#include <gtest/gtest.h>

#include <chrono>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/session.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace session_test {

using namespace std::chrono;
using test::frames_in;
using test::valset;

nmea::Fix fix_at(milliseconds since_midnight, bool has_fix = true) {
  nmea::Fix f;
  f.time_utc = sys_days{year{2026} / November / 24} + since_midnight;
  f.quality = has_fix ? nmea::FixQuality::gps : nmea::FixQuality::none;
  f.lat_deg = 47.0;
  f.lon_deg = 8.0;
  return f;
}

SessionSettings f9p_nmea_only() {
  SessionSettings s;
  s.start.model = ReceiverModel::ublox_f9p;
  s.start.measurement_period = milliseconds{100};
  return s;
}

TEST(UbxSession, StartsWithNmeaOnly) {
  Session session(f9p_nmea_only());
  std::string out;
  session.append_solution(epoch_of(fix_at(hours{12})), out);
  EXPECT_EQ(out.rfind("$GPRMC", 0), 0u);
  EXPECT_TRUE(frames_in(out).empty());
}

// As a u-blox 8 or F9 writes an epoch (gpsd's recorded streams; u-blox's description of NAV-EOE):
// the NAV messages, then the NMEA sentences, then NAV-EOE with the epoch's iTOW, once gpsd's
// configuration (CFG-MSG) turned NAV-DOP, NAV-PVT and NAV-EOE on.
TEST(UbxSession, EpochIsNavMessagesThenNmeaThenEndOfEpoch) {
  Session session(f9p_nmea_only());
  for (const char* on : {"0104 01", "0107 01", "0161 01"}) session.client_wrote(frame_bytes(msg::cfg_msg, test::unhex(on)));
  (void)session.take_reply();
  std::string out;
  session.append_solution(epoch_of(fix_at(hours{12})), out);
  const auto frames = frames_in(out);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].id, msg::nav_dop);
  EXPECT_EQ(frames[1].id, msg::nav_pvt);
  EXPECT_EQ(frames[2].id, msg::nav_eoe);
  EXPECT_EQ(get_u4(frames[2].payload, 0), get_u4(frames[1].payload, 0));  // the same iTOW
  const std::size_t rmc = out.find("$GPRMC"), last_sentence = out.rfind("\r\n");
  ASSERT_NE(rmc, std::string::npos);
  EXPECT_LT(out.find(frame_bytes(msg::nav_pvt, frames[1].payload)), rmc);
  EXPECT_EQ(out.substr(last_sentence + 2), frame_bytes(msg::nav_eoe, frames[2].payload));
}

TEST(UbxSession, ConfiguredFiveHertzPvtOnlyOnTheGrid) {
  Session session(f9p_nmea_only());
  session.client_wrote(frame_bytes(msg::cfg_valset, valset({{key::uart1outprot_nmea, 0},
                                                             {key::msgout_nav_pvt_i2c + 1, 1},
                                                             {key::rate_meas, 200}})));
  const auto reply = frames_in(session.take_reply());
  ASSERT_EQ(reply.size(), 1u);
  EXPECT_EQ(reply[0], test::ack_of(msg::cfg_valset));
  EXPECT_TRUE(session.take_reply().empty());
  const auto effects = session.take_effects();
  ASSERT_EQ(effects.size(), 1u);
  EXPECT_EQ(std::get<MeasurementPeriodChanged>(effects[0]).period, milliseconds{200});

  std::vector<std::uint32_t> tows;
  for (int k = 0; k < 10; ++k) {  // one second of 10 Hz epochs
    std::string out;
    session.append_solution(epoch_of(fix_at(hours{12} + milliseconds{100 * k})), out);
    for (const Frame& f : frames_in(out)) {
      EXPECT_EQ(f.id, msg::nav_pvt);
      tows.push_back(get_u4(f.payload, 0));
    }
    EXPECT_EQ(out.find('$'), std::string::npos);
  }
  ASSERT_EQ(tows.size(), 5u);
  for (std::size_t i = 1; i < tows.size(); ++i) EXPECT_EQ(tows[i] - tows[i - 1], 200u);
}

TEST(UbxSession, PollIsAnsweredWithTheNextSolutionOnly) {
  Session session(f9p_nmea_only());
  session.client_wrote(frame_bytes(msg::nav_dop, ""));
  EXPECT_TRUE(session.take_reply().empty());
  std::string first, second;
  session.append_solution(epoch_of(fix_at(hours{12})), first);
  session.append_solution(epoch_of(fix_at(hours{12} + milliseconds{100})), second);
  ASSERT_EQ(frames_in(first).size(), 1u);
  EXPECT_EQ(frames_in(first)[0].id, msg::nav_dop);
  EXPECT_TRUE(frames_in(second).empty());
}

TEST(UbxSession, BaudAndColdStartAreEffectsForTheCaller) {
  Session session(f9p_nmea_only());
  session.client_wrote(frame_bytes(msg::cfg_valset, valset({{key::uart1_baudrate, 115200}})) +
                       frame_bytes(msg::cfg_rst, test::unhex("ffff 0200")));
  EXPECT_EQ(frames_in(session.take_reply()).size(), 1u);  // the VALSET's ACK; CFG-RST is not answered
  const auto effects = session.take_effects();
  ASSERT_EQ(effects.size(), 2u);
  EXPECT_EQ(std::get<BaudChanged>(effects[0]).baud, 115200u);
  EXPECT_TRUE(std::holds_alternative<ColdStart>(effects[1]));
}

// The receiver's run time, TTFF and time validity are the epoch's (model/receiver_clock.hpp keeps
// them): NAV-STATUS writes what the epoch says.
TEST(UbxSession, StatusWritesTheEpochsRunTimeAndTimeToFirstFix) {
  Session session(f9p_nmea_only());
  session.client_wrote(frame_bytes(msg::cfg_msg, test::unhex("0103 01")));
  std::string out;
  ReceiverEpoch e = epoch_of(fix_at(hours{12} + milliseconds{2500}, true));
  e.status.since_start = milliseconds{2500};
  e.status.time_to_first_fix = milliseconds{2400};
  e.status.time = {.valid = true, .resolved = false, .confirmed = false};
  session.append_solution(e, out);
  const auto frames = frames_in(out);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(get_u4(frames[0].payload, 8), 2400u);   // ttff
  EXPECT_EQ(get_u4(frames[0].payload, 12), 2500u);  // msss
  EXPECT_EQ(get_u1(frames[0].payload, 5) & 0x0C, 0x0C);  // week and time of week valid
}

// Each connection has its own frame reader and its own answers (issue 22 point 8): two clients
// writing their polls half by half at once are each answered, to themselves; a client that went
// in the middle of a frame whose header announced 1000 bytes leaves nothing for the next one.
TEST(UbxSession, EachClientHasItsOwnReaderAndItsOwnAnswers) {
  Session session(f9p_nmea_only());
  const std::string mon_ver = frame_bytes(msg::mon_ver, "");
  const std::string rate = frame_bytes(msg::cfg_rate, "");
  session.client_wrote(mon_ver.substr(0, 3), 1);
  session.client_wrote(rate.substr(0, 5), 2);
  session.client_wrote(mon_ver.substr(3), 1);
  session.client_wrote(rate.substr(5), 2);
  const auto to_1 = frames_in(session.take_reply(1));
  const auto to_2 = frames_in(session.take_reply(2));
  ASSERT_EQ(to_1.size(), 1u);
  EXPECT_EQ(to_1[0].id, msg::mon_ver);
  ASSERT_EQ(to_2.size(), 2u);
  EXPECT_EQ(to_2[0].id, msg::cfg_rate);
  EXPECT_EQ(to_2[1], test::ack_of(msg::cfg_rate));
  EXPECT_EQ(session.reader_stats().frames_ok, 2u);

  session.client_wrote(std::string("\xb5\x62\x06\x01\xe8\x03\x01\x02", 8), 3);  // 1000 bytes announced
  session.client_left(3);
  session.client_wrote(mon_ver, 3);  // the same id again: a new reader
  EXPECT_EQ(frames_in(session.take_reply(3)).size(), 1u);
}

// Answers wait for their client up to Session::max_reply_bytes; past that a message's answer is
// dropped whole (the poll's answer and its ACK together) and counted, as a u-blox's TX buffer.
TEST(UbxSession, AnswersPastTheLimitAreDroppedWholeAndCounted) {
  Session session(f9p_nmea_only());
  std::string polls;
  for (int i = 0; i < 3000; ++i) polls += frame_bytes(msg::cfg_rate, "");  // 3000 x 24 bytes of answers
  session.client_wrote(polls, 1);
  const std::string reply = session.take_reply(1);
  const auto frames = frames_in(reply);
  const std::size_t kept = Session::max_reply_bytes / 24;
  EXPECT_EQ(reply.size(), kept * 24);
  ASSERT_EQ(frames.size(), 2 * kept);
  EXPECT_EQ(frames.back(), test::ack_of(msg::cfg_rate));
  EXPECT_EQ(session.stats().answers_dropped, 3000 - kept);
  EXPECT_EQ(session.stats().answer_bytes_dropped, (3000 - kept) * 24);
}

}  // namespace session_test
}  // namespace
}  // namespace gpsemu::ubx

namespace gpsemu::ubx {
namespace {
namespace session_test {

std::string cfg_rate_frame(std::uint16_t meas_ms, std::uint16_t nav_rate) {
  std::string p;
  put_u2(p, meas_ms);
  put_u2(p, nav_rate);
  put_u2(p, 1);
  return frame_bytes(msg::cfg_rate, p);
}

// Issue 22, point 2: after CFG-RATE 65535 ms x 127 the next solution is 2.3 hours away; 100 000
// NAV-PVT polls and CFG-RST/CFG-RATE writes meanwhile must not pile up (a u-blox answers a poll
// kind once with its next solution, and applies the last setting).
TEST(UbxSession, PollsAndEffectsWaitingForASolutionAreBoundedAndCounted) {
  Session session(f9p_nmea_only());
  session.client_wrote(cfg_rate_frame(65535, 127));
  std::string polls;
  for (int k = 0; k < 1000; ++k) polls += frame_bytes(msg::nav_pvt, "") + frame_bytes(msg::nav_dop, "");
  for (int round = 0; round < 50; ++round) session.client_wrote(polls);
  for (int k = 0; k < 1000; ++k) {
    session.client_wrote(frame_bytes(msg::cfg_rst, test::unhex("ffff 0200")));
    session.client_wrote(cfg_rate_frame(k % 2 == 0 ? 200 : 500, 1));
  }
  (void)session.take_reply();
  EXPECT_EQ(session.polls_waiting(), 2u);  // NAV-PVT and NAV-DOP, once each
  EXPECT_EQ(session.stats().polls_merged, 100'000u - 2u);
  EXPECT_EQ(session.effects_waiting(), 2u);  // one period, one cold start
  EXPECT_EQ(session.stats().effects_superseded, 2000u + 1u - 2u);
  const auto effects = session.take_effects();
  ASSERT_EQ(effects.size(), 2u);
  // The newest of each kind, in the order the newest arrived: the last CFG-RST, then the last rate.
  EXPECT_TRUE(std::holds_alternative<ColdStart>(effects[0]));
  EXPECT_EQ(std::get<MeasurementPeriodChanged>(effects[1]).period, milliseconds{500});
  // The next solution answers each polled kind once.
  std::string out;
  session.append_solution(epoch_of(fix_at(hours{12})), out);
  std::size_t pvt = 0, dop = 0;
  for (const Frame& f : frames_in(out)) {
    pvt += f.id == msg::nav_pvt ? 1 : 0;
    dop += f.id == msg::nav_dop ? 1 : 0;
  }
  EXPECT_EQ(pvt, 1u);
  EXPECT_EQ(dop, 1u);
  EXPECT_EQ(session.polls_waiting(), 0u);
}

SessionSettings model_session(ReceiverModel model) {
  SessionSettings s;
  s.start.model = model;
  s.start.sentences = {};
  return s;
}

std::vector<MessageId> ids_of(const std::string& bytes) {
  std::vector<MessageId> ids;
  for (const Frame& f : frames_in(bytes)) ids.push_back(f.id);
  return ids;
}

std::string cfg_msg(MessageId id, std::uint8_t rate) {
  return frame_bytes(msg::cfg_msg, std::string{char(id.msg_class), char(id.msg_id), char(rate)});
}

TEST(UbxSession, M8WritesSvinfoAndMonHwAndNaksWhatItLacks) {
  Session session(model_session(ReceiverModel::ublox_m8n));
  for (const MessageId id : {msg::nav_svinfo, msg::mon_hw, msg::nav_clock, msg::nav_sig, msg::mon_rf, msg::nav_hpposllh}) {
    session.client_wrote(cfg_msg(id, 1));
  }
  const auto reply = frames_in(session.take_reply());
  ASSERT_EQ(reply.size(), 6u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(reply[i], test::ack_of(msg::cfg_msg)) << i;
  for (std::size_t i = 3; i < 6; ++i) EXPECT_EQ(reply[i], test::nak_of(msg::cfg_msg)) << i;
  session.client_wrote(frame_bytes(msg::mon_rf, "") + frame_bytes(msg::nav_sig, ""));  // polls: no answer
  std::string out;
  session.append_solution(epoch_of(fix_at(hours{12})), out);
  EXPECT_EQ(ids_of(out), (std::vector<MessageId>{msg::nav_clock, msg::nav_svinfo, msg::mon_hw}));
}

TEST(UbxSession, F9pWritesSigRfHpposllhAndNaksSvinfo) {
  Session session(model_session(ReceiverModel::ublox_f9p));
  constexpr std::uint32_t uart1 = 1;
  session.client_wrote(frame_bytes(msg::cfg_valset, valset({{*msgout_key(msg::nav_sig, Port::i2c) + uart1, 1},
                                                             {*msgout_key(msg::mon_rf, Port::i2c) + uart1, 1},
                                                             {*msgout_key(msg::nav_hpposllh, Port::i2c) + uart1, 1}})));
  session.client_wrote(cfg_msg(msg::nav_svinfo, 1));
  session.client_wrote(frame_bytes(msg::nav_svinfo, "") + frame_bytes(msg::mon_hw, ""));  // SVINFO: no answer
  const auto reply = frames_in(session.take_reply());
  ASSERT_EQ(reply.size(), 2u);
  EXPECT_EQ(reply[0], test::ack_of(msg::cfg_valset));
  EXPECT_EQ(reply[1], test::nak_of(msg::cfg_msg));
  std::string out;
  session.append_solution(epoch_of(fix_at(hours{12})), out);
  // The messages on, by class and id, then the polled MON-HW.
  EXPECT_EQ(ids_of(out), (std::vector<MessageId>{msg::nav_hpposllh, msg::nav_sig, msg::mon_rf, msg::mon_hw}));
}

TEST(UbxSession, M9nNaksTheHighPrecisionKeys) {
  StartSettings start;
  start.model = ReceiverModel::ublox_m9n;
  ConfigMachine m(start);
  const std::uint32_t hpposllh_uart1 = *msgout_key(msg::nav_hpposllh, Port::uart1);
  EXPECT_EQ(test::send(m, msg::cfg_valset, valset({{key::msgout_nav_pvt_i2c + 1, 1}, {hpposllh_uart1, 1}})).frames,
            std::vector<Frame>{test::nak_of(msg::cfg_valset)});
  EXPECT_EQ(m.settings().rate(msg::nav_pvt, Port::i2c), 0);  // nothing of the refused VALSET applied
  EXPECT_EQ(test::send(m, msg::cfg_valget, test::valget({hpposllh_uart1})).frames,
            std::vector<Frame>{test::nak_of(msg::cfg_valget)});
  EXPECT_EQ(test::send(m, msg::cfg_valset, valset({{*msgout_key(msg::nav_sig, Port::uart1), 1}})).frames,
            std::vector<Frame>{test::ack_of(msg::cfg_valset)});
}

// CFG-MSGOUT-UBX_NAV_SOL_<port> (0x20910001 + port, in u-blox's generation-9 key list): NAV-SOL
// turned on by VALSET is written, as by CFG-MSG (issue 36: it was ACKed, read back and never sent).
TEST(UbxSession, NavSolTurnedOnByValsetIsWrittenOnM9nAndF9p) {
  for (const ReceiverModel model : {ReceiverModel::ublox_m9n, ReceiverModel::ublox_f9p}) {
    Session session(model_session(model));
    constexpr std::uint32_t nav_sol_uart1 = 0x20910002;
    session.client_wrote(frame_bytes(msg::cfg_valset, valset({{nav_sol_uart1, 1}})));
    EXPECT_EQ(frames_in(session.take_reply()), std::vector<Frame>{test::ack_of(msg::cfg_valset)});
    std::string out;
    session.append_solution(epoch_of(fix_at(hours{12})), out);
    EXPECT_EQ(ids_of(out), std::vector<MessageId>{msg::nav_sol}) << model_info(model).name;
  }
}

// NAV-SVINFO and NAV-SBAS left with protocol 27: a u-blox 9 NAKs their CFG-MSGOUT keys
// (CFG-MSGOUT-UBX_NAV_SVINFO_UART1 0x2091000c, CFG-MSGOUT-UBX_NAV_SBAS_UART1 0x2091006b) in a
// VALSET, as it NAKs them in CFG-MSG, and a VALGET of them.
TEST(UbxSession, U9NaksTheSvinfoAndSbasKeys) {
  for (const ReceiverModel model : {ReceiverModel::ublox_m9n, ReceiverModel::ublox_f9p}) {
    StartSettings start;
    start.model = model;
    ConfigMachine m(start);
    for (const std::uint32_t k : {0x2091000cu, 0x2091006bu}) {
      EXPECT_EQ(test::send(m, msg::cfg_valset, valset({{k, 1}})).frames, std::vector<Frame>{test::nak_of(msg::cfg_valset)})
          << std::hex << k << " " << model_info(model).name;
      EXPECT_EQ(test::send(m, msg::cfg_valget, test::valget({k})).frames, std::vector<Frame>{test::nak_of(msg::cfg_valget)});
    }
  }
}

// CFG-RST is a cold start effect for the channel to apply to the model (the run time starting
// again is the channel's: ChannelReset.ACfgRstColdStartStartsTheRunTimeAndTheTimeAgain).
TEST(UbxSession, ColdResetIsAColdStartEffect) {
  Session session(f9p_nmea_only());
  session.client_wrote(frame_bytes(msg::cfg_rst, test::unhex("ffff 0200")));
  const auto effects = session.take_effects();
  ASSERT_EQ(effects.size(), 1u);
  EXPECT_TRUE(std::holds_alternative<ColdStart>(effects[0]));
}

TEST(UbxSession, AHardwareResetNoClientAskedForReloadsRamWithoutAColdStartEffect) {
  Session session(f9p_nmea_only());
  // RAM only: 5 Hz and 115200 baud, and a client's cold start still waiting.
  session.client_wrote(frame_bytes(msg::cfg_valset, valset({{key::uart1_baudrate, 115200}})) + cfg_rate_frame(200, 1) +
                       frame_bytes(msg::cfg_rst, test::unhex("ffff 0200")));
  (void)session.take_reply();
  (void)session.take_effects();
  session.client_wrote(frame_bytes(msg::cfg_rst, test::unhex("ffff 0200")));
  session.hardware_reset();
  EXPECT_TRUE(session.take_reply().empty());
  EXPECT_EQ(session.machine().stats().resets, 1u) << "the client's CFG-RST (GNSS only) kept RAM";
  EXPECT_EQ(session.stats().effects_superseded, 1u) << "the client's waiting cold start";
  // The defaults again: the start period and baud, as effects; the caller restarted its receiver itself.
  const auto effects = session.take_effects();
  ASSERT_EQ(effects.size(), 2u);
  EXPECT_EQ(std::get<MeasurementPeriodChanged>(effects[0]).period, milliseconds{100});
  EXPECT_TRUE(std::holds_alternative<BaudChanged>(effects[1]));
}

}  // namespace session_test
}  // namespace
}  // namespace gpsemu::ubx
