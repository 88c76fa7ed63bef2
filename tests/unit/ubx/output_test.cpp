// What goes out with each solution: the messages the settings turn on, at their rates, in
// u-blox's order; NMEA sentences likewise; nothing of a protocol the port does not output; a
// polled message once.
#include <gtest/gtest.h>

#include "emulator/ubx/machine.hpp"
#include "emulator/ubx/output.hpp"
#include "nmea/sentences.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace output_test {

using test::send;
using test::unhex;

StartSettings nmea_and_pvt() {
  StartSettings start;
  start.model = ReceiverModel::ublox_m8n;
  start.ubx_messages = {msg::nav_pvt};
  return start;
}

TEST(UbxOutput, StartMessagesGoOutEverySolution) {
  const Settings s = start_settings(nmea_and_pvt());
  EXPECT_EQ(due_messages(s, Port::uart1, 0), std::vector<MessageId>{msg::nav_pvt});
  EXPECT_EQ(due_messages(s, Port::uart1, 7), std::vector<MessageId>{msg::nav_pvt});
  EXPECT_TRUE(due_messages(s, Port::usb, 0).empty());
  EXPECT_EQ(due_sentences(s, Port::uart1, 3), nmea::SentenceSet::ublox_default());
}

TEST(UbxOutput, RatesAndOrderFollowTheClientsConfiguration) {
  ConfigMachine m(nmea_and_pvt());
  (void)send(m, msg::cfg_msg, unhex("0121 05"));  // NAV-TIMEUTC every 5th solution
  (void)send(m, msg::cfg_msg, unhex("0102 01"));  // NAV-POSLLH every solution
  (void)send(m, msg::cfg_msg, unhex("f003 00"));  // GSV off
  (void)send(m, msg::cfg_msg, unhex("0a09 01"));  // MON-HW: after the NAV messages
  (void)send(m, msg::cfg_msg, unhex("0215 01"));  // RXM-RAWX: not encoded, never written
  const std::vector<MessageId> first = {msg::nav_posllh, msg::nav_pvt, msg::nav_timeutc, msg::mon_hw};
  EXPECT_EQ(due_messages(m.settings(), Port::uart1, 0), first);
  const std::vector<MessageId> second = {msg::nav_posllh, msg::nav_pvt, msg::mon_hw};
  EXPECT_EQ(due_messages(m.settings(), Port::uart1, 1), second);
  EXPECT_FALSE(due_sentences(m.settings(), Port::uart1, 0).contains(nmea::SentenceType::gsv));
  EXPECT_TRUE(due_sentences(m.settings(), Port::uart1, 0).contains(nmea::SentenceType::gga));
}

TEST(UbxOutput, PortWithoutNmeaOutputWritesNoSentences) {
  ConfigMachine m(nmea_and_pvt());
  (void)m.feed(nmea::frame("PUBX,41,1,0007,0001,9600,0"));
  EXPECT_TRUE(due_sentences(m.settings(), Port::uart1, 0).empty());
  EXPECT_EQ(due_messages(m.settings(), Port::uart1, 0), std::vector<MessageId>{msg::nav_pvt});
}

TEST(UbxOutput, SolutionBytesAreTheDueFramesThenThePolledOnes) {
  const Settings s = start_settings(nmea_and_pvt());
  nmea::Fix fix;
  fix.quality = nmea::FixQuality::gps;
  std::string out;
  const MessageId polled[] = {msg::nav_pvt, msg::nav_dop};
  append_solution(out, s, Port::uart1, 0, fix, NavExtras{}, polled);
  const auto frames = test::frames_in(out);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].id, msg::nav_pvt);
  EXPECT_EQ(frames[1].id, msg::nav_dop);
}

TEST(UbxOutput, WidestSolutionCountsEveryMessageOnWithAllSatellites) {
  ConfigMachine m(nmea_and_pvt());
  EXPECT_EQ(widest_solution_ubx_bytes(m.settings(), Port::uart1), 100u);  // NAV-PVT: 92 + 8
  (void)send(m, msg::cfg_msg, unhex("0135 05"));  // NAV-SAT every 5th solution still counts
  EXPECT_EQ(widest_solution_ubx_bytes(m.settings(), Port::uart1), 100u + 8 + 8 + 12 * nmea::max_satellites);
  (void)m.feed(nmea::frame("PUBX,41,1,0007,0002,9600,0"));  // NMEA only out
  EXPECT_EQ(widest_solution_ubx_bytes(m.settings(), Port::uart1), 0u);
}

// What RTK adds to an F9P's epoch: NAV-RELPOSNED (64 + 8) when on, and RXM-RTCM's reports of a
// base epoch's RTCM3 (10 x (8 + 8)) when on and the port takes RTCM3.
TEST(UbxOutput, WidestSolutionCountsNavRelposnedAndRxmRtcm) {
  StartSettings start = nmea_and_pvt();
  start.model = ReceiverModel::ublox_f9p;
  ConfigMachine m(start);
  const std::size_t pvt = widest_solution_ubx_bytes(m.settings(), Port::uart1, ReceiverModel::ublox_f9p);
  (void)send(m, msg::cfg_msg, unhex("013C 01"));  // NAV-RELPOSNED
  const std::size_t relpos = widest_solution_ubx_bytes(m.settings(), Port::uart1, ReceiverModel::ublox_f9p);
  EXPECT_EQ(relpos, pvt + 72);
  (void)send(m, msg::cfg_msg, unhex("0232 01"));  // RXM-RTCM
  EXPECT_EQ(widest_solution_ubx_bytes(m.settings(), Port::uart1, ReceiverModel::ublox_f9p),
            relpos + rtcm_messages_per_solution_budget * 16);
  // RTCM3 input off on UART1 (CFG-UART1INPROT-RTCM3X): nothing to report.
  (void)send(m, msg::cfg_valset, test::valset({{0x10730004, 0}}));
  EXPECT_EQ(widest_solution_ubx_bytes(m.settings(), Port::uart1, ReceiverModel::ublox_f9p), relpos);
}

}  // namespace output_test
}  // namespace
}  // namespace gpsemu::ubx
