// ArduPilot's AP_GPS_UBLOX start-up, played against the state machine: the detection blob
// (CFG-MSG NAV-SOL 1 and $PUBX,41 to 115200, UBX only), then _request_next_config()'s steps in
// their order. ArduPilot polls each setting and writes it back only when it differs from what it
// wants (GPS_RATE_MS 200, GPS_NAVFILTER 8 airborne < 4 g, RATE_PVT 1, RATE_TIMEGPS 5, RATE_HW 5,
// GPS_SBAS_MODE and GPS_GNSS_MODE left alone); the test does the same with the answers it gets.
// On an F9 the GNSS poll is skipped and CFG-TMODE-MODE is read with CFG-VALGET. With
// GPS_AUTO_CONFIG 1 or 2 (2 adds DroneCAN GPSes: a serial u-blox is configured the same),
// GPS_SBAS_MODE 0 and GPS_GNSS_MODE 65 (GPS + GLONASS), the SBAS and GNSS steps write their
// settings and GPS_SAVE_CFG 2 saves them (CFG-CFG): a power cycle (CFG-RST hardware reset) keeps
// everything, and the next round writes nothing.
#include <gtest/gtest.h>

#include <string>

#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/machine.hpp"
#include "nmea/sentences.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace ardupilot_sequence_test {

using namespace std::chrono_literals;
using test::ack_of;
using test::effects_of;
using test::send;
using test::unhex;

constexpr MessageId nav_svinfo{0x01, 0x30};
constexpr MessageId mon_hw{0x0A, 0x09};
constexpr MessageId mon_hw2{0x0A, 0x0B};
constexpr std::uint32_t tmode_mode = 0x20030001;

/// ArduPilot's side of the handshake: what it wants and what it learnt.
class ArduPilotDriver {
 public:
  explicit ArduPilotDriver(ConfigMachine& m) : m_(m) {}

  void detection_blob() {
    Answer a = m_.feed(unhex("b562 0601 0300 010601 124f") + "$PUBX,41,1,0023,0001,115200,0*1C\r\n");
    const auto frames = test::frames_in(a.bytes);
    EXPECT_EQ(frames, std::vector<Frame>{ack_of(msg::cfg_msg)});  // nothing for the PUBX
    EXPECT_EQ(effects_of<BaudChanged>(a.effects).at(0).baud, 115200u);
    EXPECT_FALSE(effects_of<OutputProtocolsChanged>(a.effects).at(0).nmea);
  }

  /// STEP_<message>: poll the rate (CFG-MSG, 2 bytes), set it when it is not `desired`.
  void rate_step(MessageId id, std::uint8_t desired) {
    auto got = send(m_, msg::cfg_msg, std::string{char(id.msg_class), char(id.msg_id)});
    ASSERT_EQ(got.frames.size(), 2u);
    ASSERT_EQ(got.frames[0].id, msg::cfg_msg);
    ASSERT_EQ(got.frames[0].payload.size(), 8u);  // rates of 6 ports: read at _ublox_port
    EXPECT_EQ(got.frames[1], ack_of(msg::cfg_msg));
    const std::uint8_t rate = get_u1(got.frames[0].payload, 2 + port_);
    if (rate == desired) return;
    got = send(m_, msg::cfg_msg, std::string{char(id.msg_class), char(id.msg_id), char(desired)});
    EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_msg)});
    ++writes_;
  }

  void nav_rate_step() {
    auto got = send(m_, msg::cfg_rate);
    ASSERT_EQ(got.frames.size(), 2u);
    const std::string& p = got.frames[0].payload;
    if (get_u2(p, 0) == 200 && get_u2(p, 2) == 1 && get_u2(p, 4) == 0) return;
    got = send(m_, msg::cfg_rate, unhex("c800 0100 0000"));
    EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_rate)});
    ++writes_;
  }

  void port_step() {
    const auto got = send(m_, msg::cfg_prt);
    ASSERT_EQ(got.frames.size(), 2u);
    port_ = get_u1(got.frames[0].payload, 0);
  }

  void nav_settings_step() {
    auto got = send(m_, msg::cfg_nav5);
    ASSERT_EQ(got.frames.size(), 2u);
    std::string nav5 = got.frames[0].payload;
    ASSERT_EQ(nav5.size(), 36u);
    if (get_u1(nav5, 2) == 8) return;
    nav5[0] = 0x01;  // mask: dynModel only
    nav5[1] = 0;
    nav5[2] = 8;
    got = send(m_, msg::cfg_nav5, nav5);
    EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_nav5)});
    ++writes_;
  }

  void poll_answered(MessageId id) {
    const auto got = send(m_, id);
    ASSERT_EQ(got.frames.size(), 2u);
    EXPECT_EQ(got.frames[0].id, id);
    EXPECT_EQ(got.frames[1], ack_of(id));
  }

  std::string version_step() {
    const auto got = send(m_, msg::mon_ver);
    EXPECT_EQ(got.frames.size(), 1u);
    return got.frames.empty() ? std::string{} : got.frames[0].payload.substr(30, 8);
  }

  /// The configuration loop once through (_request_next_config, classic steps).
  void configure_round(bool f9) {
    rate_step(msg::nav_pvt, 1);           // STEP_PVT
    nav_rate_step();                      // STEP_NAV_RATE
    rate_step(msg::nav_sol, 1);           // STEP_SOL (no PVT seen yet: wanted)
    port_step();                          // STEP_PORT
    rate_step(msg::nav_status, 1);        // STEP_STATUS
    rate_step(msg::nav_posllh, 1);        // STEP_POSLLH
    rate_step(msg::nav_velned, 1);        // STEP_VELNED
    rate_step(msg::nav_timegps, 5);       // STEP_TIMEGPS
    {  // STEP_POLL_SVINFO: an M8 answers with the next solution, an F9 (protocol 27+) not at all
      const auto got = send(m_, nav_svinfo);
      EXPECT_TRUE(got.frames.empty());
      EXPECT_EQ(effects_of<PollOnce>(got.effects).size(), f9 ? 0u : 1u);
    }
    nav_settings_step();                  // STEP_POLL_NAV
    if (f9) {                             // STEP_TMODE (F9 config)
      const auto got = send(m_, msg::cfg_valget, test::valget({tmode_mode}));
      ASSERT_EQ(got.frames.size(), 2u);
      EXPECT_EQ(got.frames[0].payload, unhex("01 00 0000 01000320 00"));
      EXPECT_EQ(got.frames[1], ack_of(msg::cfg_valget));
    } else {
      poll_answered(msg::cfg_gnss);       // STEP_POLL_GNSS
    }
    rate_step(msg::nav_dop, 1);           // STEP_DOP
    rate_step(mon_hw, 5);                 // STEP_MON_HW
    rate_step(mon_hw2, 5);                // STEP_MON_HW2
  }

  /// STEP_POLL_SBAS: poll CFG-SBAS, write the mode GPS_SBAS_MODE asks when it differs.
  void sbas_step(std::uint8_t mode) {
    auto got = send(m_, msg::cfg_sbas);
    ASSERT_EQ(got.frames.size(), 2u);
    std::string sbas = got.frames[0].payload;
    ASSERT_EQ(sbas.size(), 8u);
    if (get_u1(sbas, 0) == mode) return;
    sbas[0] = static_cast<char>(mode);
    EXPECT_EQ(send(m_, msg::cfg_sbas, sbas).frames, std::vector<Frame>{ack_of(msg::cfg_sbas)});
    ++writes_;
  }

  /// STEP_POLL_GNSS with GPS_GNSS_MODE `mask` (bit n: gnssId n): each block enabled or not.
  void gnss_step(std::uint8_t mask) {
    auto got = send(m_, msg::cfg_gnss);
    ASSERT_EQ(got.frames.size(), 2u);
    std::string gnss = got.frames[0].payload;
    const std::size_t blocks = get_u1(gnss, 3);
    ASSERT_EQ(gnss.size(), 4 + 8 * blocks);
    bool differs = false;
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t at = 4 + 8 * b;
      const bool want = (mask >> get_u1(gnss, at)) & 1;
      const std::uint32_t flags = get_u4(gnss, at + 4);
      if (((flags & 1) != 0) == want) continue;
      differs = true;
      std::string block;
      put_u4(block, want ? (flags | 1) : (flags & ~1u));
      gnss.replace(at + 4, 4, block);
    }
    if (!differs) return;
    EXPECT_EQ(send(m_, msg::cfg_gnss, gnss).frames, std::vector<Frame>{ack_of(msg::cfg_gnss)});
    ++writes_;
  }

  /// GPS_SAVE_CFG 2: CFG-CFG save (12 bytes: BBR and flash) once something was written.
  void save_if_changed() {
    if (writes_ == 0) return;
    std::string p;
    put_u4(p, 0);
    put_u4(p, 0xFFFF);
    put_u4(p, 0);
    EXPECT_EQ(send(m_, msg::cfg_cfg, p).frames, std::vector<Frame>{ack_of(msg::cfg_cfg)});
  }

  [[nodiscard]] int writes() const { return writes_; }

 private:
  ConfigMachine& m_;
  std::uint8_t port_ = 1;
  int writes_ = 0;
};

ConfigMachine machine_of(ReceiverModel model) {
  StartSettings start;
  start.model = model;
  return ConfigMachine(start);
}

void expect_ardupilot_rates(const Settings& s, ReceiverModel model) {
  EXPECT_EQ(s.output_period(), 200ms);
  test::expect_solutions_every(s, model, 200ms);  // the receiver's epochs: 5 Hz on the second
  EXPECT_EQ(s.time_ref, 0);
  EXPECT_EQ(s.dyn_model(), 8);
  EXPECT_EQ(s.ports[1].baud, 115200u);
  EXPECT_EQ(s.ports[1].out_proto_mask, proto_ubx);
  for (const MessageId id : {msg::nav_pvt, msg::nav_sol, msg::nav_status, msg::nav_posllh, msg::nav_velned,
                             msg::nav_dop}) {
    EXPECT_EQ(s.rate(id, Port::uart1), 1) << int(id.msg_id);
  }
  EXPECT_EQ(s.rate(msg::nav_timegps, Port::uart1), 5);
  EXPECT_EQ(s.rate(mon_hw, Port::uart1), 5);
}

TEST(UbxArduPilotSequence, M8nIsConfiguredInOneRoundAndTheSecondRoundChangesNothing) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  ArduPilotDriver driver(m);
  driver.detection_blob();
  driver.configure_round(false);
  EXPECT_EQ(driver.version_step(), "00080000");  // STEP_VERSION: UBLOX_M8
  EXPECT_EQ(driver.writes(), 10);  // PVT, rate, STATUS, POSLLH, VELNED, TIMEGPS, NAV5, DOP, HW, HW2
  expect_ardupilot_rates(m.settings(), m.model());
  ArduPilotDriver again(m);
  again.configure_round(false);
  EXPECT_EQ(again.writes(), 0);
  EXPECT_EQ(m.stats().naks, 0u);
}

TEST(UbxArduPilotSequence, F9pAnswersTheTmodeValgetAndTheClassicSteps) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_f9p);
  ArduPilotDriver driver(m);
  driver.detection_blob();
  driver.configure_round(true);
  EXPECT_EQ(driver.version_step(), "00190000");  // STEP_VERSION: UBLOX_F9
  expect_ardupilot_rates(m.settings(), m.model());
  EXPECT_EQ(m.stats().naks, 0u);
}

/// GPS_AUTO_CONFIG 1 and 2 (serial u-blox: the same configuration).
class UbxArduPilotAutoConfig : public testing::TestWithParam<int> {};

TEST_P(UbxArduPilotAutoConfig, SbasOffAndGpsGlonassAreWrittenSavedAndSurviveAPowerCycle) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);  // the factory state: NMEA on, no UBX output
  ArduPilotDriver driver(m);
  driver.detection_blob();
  driver.configure_round(false);
  driver.sbas_step(0);
  driver.gnss_step(65);
  EXPECT_EQ(driver.writes(), 12);  // the classic 10, SBAS, GNSS
  driver.save_if_changed();
  // Power cycle: RAM reloads from BBR/flash.
  (void)send(m, msg::cfg_rst, unhex("0000 00 00"));
  EXPECT_EQ(m.stats().resets, 1u);
  expect_ardupilot_rates(m.settings(), m.model());
  EXPECT_EQ(get_u1(m.settings().sbas, 0), 0);
  for (std::size_t b = 0; b < get_u1(m.settings().gnss, 3); ++b) {
    const std::size_t at = 4 + 8 * b;
    const bool on = (get_u4(m.settings().gnss, at + 4) & 1) != 0;
    EXPECT_EQ(on, get_u1(m.settings().gnss, at) == 0 || get_u1(m.settings().gnss, at) == 6) << "gnssId " << b;
  }
  ArduPilotDriver again(m);
  again.configure_round(false);
  again.sbas_step(0);
  again.gnss_step(65);
  EXPECT_EQ(again.writes(), 0) << "GPS_AUTO_CONFIG " << GetParam() << ": the saved configuration is what ArduPilot wants";
  EXPECT_EQ(m.stats().naks, 0u);
}

INSTANTIATE_TEST_SUITE_P(GpsAutoConfig, UbxArduPilotAutoConfig, testing::Values(1, 2));

}  // namespace ardupilot_sequence_test
}  // namespace
}  // namespace gpsemu::ubx
