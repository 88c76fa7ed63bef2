// Other drivers' start-up sequences, played frame by frame against a factory-state receiver (NMEA
// on, no UBX output: StartSettings' defaults), each frame written here from the driver's source:
// - the ROS driver (KumarRobotics/ublox, ublox_gps: Gps::initializeSerial / configUart1, the
//   MON-VER poll, UbloxNode::configureUblox: CFG-RATE, CFG-SBAS, CFG-NAVX5 (PPP), CFG-NAV5 three
//   times (dynamic model, fix mode, dead-reckoning limit), UbloxFirmware8::configureUblox: the
//   CFG-GNSS poll and, when it differs, the write and a GNSS-only cold reset, then the rates of the
//   messages it subscribes to (CFG-MSG) and the save (CFG-CFG with a device mask): every step
//   waits for its ACK, so each must be ACK-ACKed;
// - gpsd's ubxtool presets (gps/ubx.py): -p MON-VER, -e BINARY and -d NMEA (CFG-MSG runs for
//   protocol 27+), -p SAVE, -p COLDBOOT, -p RESET (CFG-CFG clear and load, device mask 0x17);
// - u-center's first polls on connecting (closed source: the polls its views issue, not a capture):
//   MON-VER, CFG-PRT of each port, CFG-RATE, CFG-NAV5, CFG-GNSS, CFG-SBAS, a CFG-MSG poll and, on a
//   generation-9 receiver, CFG-VALGET of RAM and of the defaults.
#include <gtest/gtest.h>

#include <string>

#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/config_layers.hpp"
#include "emulator/ubx/machine.hpp"
#include "emulator/ubx/output.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace driver_sequences_test {

using namespace std::chrono_literals;
using test::ack_of;
using test::send;
using test::unhex;

constexpr MessageId cfg_navx5{0x06, 0x23};
constexpr MessageId mon_hw{0x0A, 0x09};

ConfigMachine factory(ReceiverModel model) {
  StartSettings start;
  start.model = model;
  return ConfigMachine(start);
}

std::string cfg_msg3(MessageId id, std::uint8_t rate) {
  return std::string{static_cast<char>(id.msg_class), static_cast<char>(id.msg_id), static_cast<char>(rate)};
}

/// Sends one configuration message and expects the ACK-ACK the driver waits for.
void expect_acked(ConfigMachine& m, MessageId id, const std::string& payload) {
  EXPECT_EQ(send(m, id, payload).frames, std::vector<Frame>{ack_of(id)}) << "class " << int(id.msg_class) << " id "
                                                                          << int(id.msg_id);
}

/// A poll answered with the message, then ACK-ACK.
std::string expect_poll(ConfigMachine& m, MessageId id, const std::string& payload = {}) {
  const auto got = send(m, id, payload);
  EXPECT_EQ(got.frames.size(), 2u) << "poll of class " << int(id.msg_class) << " id " << int(id.msg_id);
  if (got.frames.size() != 2) return {};
  EXPECT_EQ(got.frames[0].id, id);
  EXPECT_EQ(got.frames[1], ack_of(id));
  return got.frames[0].payload;
}

/// CFG-NAV5 with one parameter group (mask) set.
std::string nav5_with(std::uint16_t mask, std::size_t offset, std::uint8_t value) {
  std::string p(36, '\0');
  p[0] = static_cast<char>(mask & 0xFF);
  p[1] = static_cast<char>(mask >> 8);
  p[offset] = static_cast<char>(value);
  return p;
}

void ros_ublox_gps(ConfigMachine& m) {
  // initializeSerial -> configUart1(115200, in UBX|NMEA|RTCM3, out UBX): CFG-PRT of UART1.
  std::string prt;
  put_u1(prt, 1);
  put_zeros(prt, 3);
  put_u4(prt, 0x08D0);
  put_u4(prt, 115200);
  put_u2(prt, 0x0023);
  put_u2(prt, 0x0001);
  put_zeros(prt, 4);
  expect_acked(m, msg::cfg_prt, prt);
  EXPECT_EQ(send(m, msg::mon_ver).frames.size(), 1u);  // processMonVer: lists SBAS, so SBAS is configured
  expect_acked(m, msg::cfg_rate, unhex("c800 0100 0100"));  // 200 ms, GPS time
  expect_acked(m, msg::cfg_sbas, unhex("00 03 03 00 00000000"));  // SBAS off
  std::string navx5(40, '\0');
  navx5[0] = 2;  // version 2 (protocol 18+), usePPP 0
  expect_acked(m, cfg_navx5, navx5);
  expect_acked(m, msg::cfg_nav5, nav5_with(0x0001, 2, 8));   // dynModel airborne < 4 g
  expect_acked(m, msg::cfg_nav5, nav5_with(0x0004, 3, 3));   // fixMode auto
  expect_acked(m, msg::cfg_nav5, nav5_with(0x0008, 13, 0));  // drLimit 0 s
  // UbloxFirmware8: GNSS as wanted (GPS, SBAS off, Galileo, GLONASS...): the default blocks
  // differ in SBAS, so it writes them and cold-resets the GNSS alone (no ACK for CFG-RST).
  std::string gnss = expect_poll(m, msg::cfg_gnss);
  ASSERT_EQ(gnss.size(), 4u + 8u * get_u1(gnss, 3));
  for (std::size_t at = 4; at < gnss.size(); at += 8) {
    if (get_u1(gnss, at) == 1) gnss[at + 4] = static_cast<char>(get_u1(gnss, at + 4) & ~1);
  }
  expect_acked(m, msg::cfg_gnss, gnss);
  EXPECT_TRUE(send(m, msg::cfg_rst, unhex("ffff 02 00")).frames.empty());
  // subscribe<NavPVT>, <NavSAT>, <MonHW>: CFG-MSG, rate 1.
  for (const MessageId id : {msg::nav_pvt, msg::nav_sat, mon_hw}) expect_acked(m, msg::cfg_msg, cfg_msg3(id, 1));
  // save: CFG-CFG saveMask (all), device BBR | flash.
  expect_acked(m, msg::cfg_cfg, unhex("00000000 ffff0000 00000000 03"));
}

TEST(UbxDriverSequences, RosUbloxGpsConfiguresAFactoryM8nAndF9pAndItsSaveSurvivesAReset) {
  for (const ReceiverModel model : {ReceiverModel::ublox_m8n, ReceiverModel::ublox_f9p}) {
    ConfigMachine m = factory(model);
    ros_ublox_gps(m);
    EXPECT_EQ(m.stats().naks, 0u) << model_info(model).name;
    // The GNSS-only cold reset kept RAM; a hardware reset later reloads the saved configuration.
    (void)send(m, msg::cfg_rst, unhex("0000 00 00"));
    const Settings& s = m.settings();
    EXPECT_EQ(s.output_period(), 200ms) << model_info(model).name;
    EXPECT_EQ(s.dyn_model(), 8);
    EXPECT_EQ(get_u1(s.sbas, 0), 0);
    EXPECT_EQ(s.ports[1].baud, 115200u);
    // NAV-PVT, NAV-SAT and MON-HW (the driver turns MON-HW on; an M8 and an F9 both have it).
    EXPECT_EQ(due_messages(s, Port::uart1, 0), (std::vector<MessageId>{msg::nav_pvt, msg::nav_sat, msg::mon_hw}));
    EXPECT_TRUE(due_sentences(s, Port::uart1, 0).empty()) << "UART1 outputs UBX only";
  }
}

TEST(UbxDriverSequences, UbxtoolPresetsBinaryNmeaSaveColdbootAndReset) {
  ConfigMachine m = factory(ReceiverModel::ublox_f9p);
  const std::string version = send(m, msg::mon_ver).frames.at(0).payload;  // -p MON-VER: PROTVER=27.31
  EXPECT_NE(version.find("PROTVER=27.31"), std::string::npos);
  // -e BINARY (protocol 27): DOP, TIMEGPS; POSECEF, PVT, VELECEF, SAT, EOE; SIG on; SOL, SVINFO
  // off; TIMELS every 255; VELNED, NAV-SBAS off. ubxtool waits for none of the ACKs.
  for (const std::uint8_t id : {0x04, 0x20, 0x01, 0x07, 0x11, 0x35, 0x61, 0x43}) {
    (void)send(m, msg::cfg_msg, cfg_msg3({0x01, id}, 1));
  }
  for (const std::uint8_t id : {0x06, 0x30}) (void)send(m, msg::cfg_msg, cfg_msg3({0x01, id}, 0));
  (void)send(m, msg::cfg_msg, cfg_msg3({0x01, 0x26}, 0xFF));
  for (const std::uint8_t id : {0x12, 0x32}) (void)send(m, msg::cfg_msg, cfg_msg3({0x01, id}, 0));
  // -d NMEA: GGA GSA GSV RMC VTG GST ZDA GBS off, and GLL.
  for (const std::uint8_t id : {0x00, 0x02, 0x03, 0x04, 0x05, 0x07, 0x08, 0x09, 0x01}) {
    (void)send(m, msg::cfg_msg, cfg_msg3({0xF0, id}, 0));
  }
  // TIMELS every 255 solutions is due at solution 0; SIG is an F9P's.
  const std::vector<MessageId> binary = {msg::nav_posecef, msg::nav_dop,    msg::nav_pvt, msg::nav_velecef,
                                         msg::nav_timegps, msg::nav_timels, msg::nav_sat, msg::nav_sig,
                                         msg::nav_eoe};
  EXPECT_EQ(due_messages(m.settings(), Port::uart1, 0), binary);
  EXPECT_TRUE(due_sentences(m.settings(), Port::uart1, 0).empty());
  // -p SAVE: CFG-CFG save 0x0f1f, device mask 0x17; then -p COLDBOOT (CFG-RST 0xffff, hardware).
  expect_acked(m, msg::cfg_cfg, unhex("00000000 1f0f0000 00000000 17"));
  const auto coldboot = send(m, msg::cfg_rst, unhex("ffff 00 00"));
  EXPECT_TRUE(coldboot.frames.empty());
  EXPECT_EQ(test::effects_of<ColdStart>(coldboot.effects).size(), 1u);
  EXPECT_EQ(due_messages(m.settings(), Port::uart1, 0), binary) << "saved: kept through the cold boot";
  // -p RESET: clear and load (0x0f1f), device mask 0x17: the defaults again, nothing stored.
  expect_acked(m, msg::cfg_cfg, unhex("1f0f0000 00000000 1f0f0000 17"));
  EXPECT_TRUE(m.stored().bbr.empty());
  EXPECT_TRUE(m.stored().flash.empty());
  EXPECT_TRUE(due_messages(m.settings(), Port::uart1, 0).empty());
  EXPECT_EQ(due_sentences(m.settings(), Port::uart1, 0), nmea::SentenceSet::ublox_default());
}

TEST(UbxDriverSequences, UCenterFirstPollsAreEachAnswered) {
  for (const ReceiverModel model : {ReceiverModel::ublox_m8n, ReceiverModel::ublox_m9n}) {
    ConfigMachine m = factory(model);
    EXPECT_EQ(send(m, msg::mon_ver).frames.size(), 1u);
    for (std::uint8_t port = 0; port <= 4; ++port) {
      const std::string prt = expect_poll(m, msg::cfg_prt, std::string(1, static_cast<char>(port)));
      ASSERT_EQ(prt.size(), 20u);
      EXPECT_EQ(get_u1(prt, 0), port);
    }
    EXPECT_EQ(get_u2(expect_poll(m, msg::cfg_rate), 0), 1000);
    EXPECT_EQ(expect_poll(m, msg::cfg_nav5).size(), 36u);
    (void)expect_poll(m, msg::cfg_gnss);
    EXPECT_EQ(expect_poll(m, msg::cfg_sbas).size(), 8u);
    EXPECT_EQ(get_u1(expect_poll(m, msg::cfg_msg, std::string{char(0xF0), char(0x00)}), 2 + 1), 1) << "GGA on UART1";
    if (model_info(model).key_value_config) {
      const std::string ram = expect_poll(m, msg::cfg_valget, test::valget({key::rate_meas}, layer_ram));
      EXPECT_EQ(get_u2(ram, 8), 1000);
      const std::string defaults = expect_poll(m, msg::cfg_valget, test::valget({key::rate_meas}, layer_default));
      EXPECT_EQ(get_u2(defaults, 8), 1000);
    }
    EXPECT_EQ(m.stats().naks, 0u) << model_info(model).name;
  }
}

}  // namespace driver_sequences_test
}  // namespace
}  // namespace gpsemu::ubx
