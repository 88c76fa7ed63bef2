// PX4's u-blox driver start-up (PX4-GPSDrivers src/ubx.cpp, GPSDriverUBX::configure() with
// auto-baud, output mode GPS, default parameters), played frame by frame in its order against
// the state machine: an F9P takes the CFG-VALSET path, an M8N NAKs the first VALSET and gets the
// classic CFG-PRT / CFG-RATE / CFG-NAV5 / CFG-MSG path. Every step PX4 waits for is answered
// within the same call (PX4 waits UBX_CONFIG_TIMEOUT = 250 ms, 2 s for the first VALSET: the
// loop must flush the answer before the next epoch), and the resulting rates are PX4's. Then the
// same bytes configure a u-blox port (ubx::Session) whose solutions a reader of PX4's fields
// (written here from u-blox's descriptions and PX4's ubx.cpp semantics) decodes: satellite_info
// from NAV-SAT (F9P) or NAV-SVINFO (M8N) lists the sky's satellites of every system, and the
// noise, AGC and jamming fields of sensor_gps come from MON-RF (F9P) or MON-HW (M8N).
#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/machine.hpp"
#include "emulator/ubx/session.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace px4_sequence_test {

using namespace std::chrono_literals;
using test::ack_of;
using test::effects_of;
using test::nak_of;
using test::valset;

std::string g_written;  // every frame the driver wrote, in order

/// PX4 writes a frame; the machine answers.
test::Exchange send(ConfigMachine& m, MessageId id, std::string_view payload = {}) {
  g_written += frame_bytes(id, payload);
  return test::send(m, id, payload);
}

// PX4's keys (src/ubx.h).
constexpr std::uint32_t uart1_stopbits = 0x20520002, uart1_databits = 0x20520003, uart1_parity = 0x20520004;
constexpr std::uint32_t uart1inprot_nmea = 0x10730002, uart1inprot_rtcm3x = 0x10730004;
constexpr std::uint32_t usbinprot_ubx = 0x10770001, usbinprot_nmea = 0x10770002, usbinprot_rtcm3x = 0x10770004;
constexpr std::uint32_t usboutprot_ubx = 0x10780001, usboutprot_nmea = 0x10780002;
constexpr std::uint32_t navspg_utcstandard = 0x2011001C;
constexpr std::uint32_t odo_use_odo = 0x10220001, odo_use_cog = 0x10220002, odo_outlpvel = 0x10220003,
                        odo_outlpcog = 0x10220004;
constexpr std::uint32_t navhpg_dgnssmode = 0x20140011, itfm_enable = 0x1041000D, sec_jamdet_hi = 0x10F60051;
constexpr std::uint32_t msgout_hpposllh_i2c = 0x20910033, msgout_relposned_i2c = 0x2091008D,
                        msgout_dop_i2c = 0x20910038, msgout_sat_i2c = 0x20910015, msgout_status_i2c = 0x2091001A,
                        msgout_mon_rf_i2c = 0x20910359, msgout_rxm_rtcm_i2c = 0x20910268;
constexpr std::uint32_t i2cinprot_ubx = 0x10710001, i2cinprot_nmea = 0x10710002, i2cinprot_rtcm3x = 0x10710004,
                        i2coutprot_ubx = 0x10720001, i2coutprot_nmea = 0x10720002, i2coutprot_rtcm3x = 0x10720004;
constexpr std::uint8_t uart1 = 1, usb = 3;  // cfgValsetPort() writes UART1 (+1) and USB (+3)

ConfigMachine machine_of(ReceiverModel model) {
  g_written.clear();
  StartSettings start;
  start.model = model;
  start.baud = 38400;  // the first baud PX4 tries
  return ConfigMachine(start);
}

/// PX4's first VALSET: UART1 8N1, UBX in and out, no NMEA.
std::string uart1_valset() {
  return valset({{uart1_stopbits, 1}, {uart1_databits, 0}, {uart1_parity, 0}, {key::uart1inprot_ubx, 1},
                 {uart1inprot_nmea, 0}, {key::uart1outprot_ubx, 1}, {key::uart1outprot_nmea, 0}});
}

/// Two CFG-PRT blocks (UART1 and USB) at `baud`, UBX+RTCM3 in, UBX out, as PX4 writes them.
std::string cfg_prt_pair(std::uint32_t baud) {
  std::string p;
  for (const std::uint8_t port : {uart1, usb}) {
    put_u1(p, port);
    put_zeros(p, 3);
    put_u4(p, 0x08D0);
    put_u4(p, baud);
    put_u2(p, 0x0021);
    put_u2(p, 0x0001);
    put_zeros(p, 4);
  }
  return p;
}

std::string cfg_msg_3(MessageId id, std::uint8_t rate) {
  return std::string{static_cast<char>(id.msg_class), static_cast<char>(id.msg_id), static_cast<char>(rate)};
}

/// What PX4's GPSDriverUBX keeps of a u-blox stream: satellite_info (svid in NAV-SVINFO's
/// numbering, used, snr, elevation, azimuth) and sensor_gps's noise_per_ms,
/// automatic_gain_control, jamming_indicator and jamming_state.
struct Px4Satellite {
  int svid = 0, used = 0, snr = 0, elevation = 0, azimuth = 0;
  friend bool operator==(const Px4Satellite&, const Px4Satellite&) = default;
};
struct Px4View {
  std::vector<Px4Satellite> satellites;
  int satellite_messages = 0;
  std::optional<int> noise_per_ms, automatic_gain_control, jamming_indicator, jamming_state;
};

/// gnssId/svId -> NAV-SVINFO's svid (u-blox 8 numbering), as PX4 converts NAV-SAT.
int svinfo_number(int gnss_id, int sv_id) {
  switch (gnss_id) {
    case 0: return sv_id;
    case 1: return sv_id;
    case 2: return sv_id + 210;
    case 3: return sv_id <= 5 ? sv_id + 158 : sv_id + 27;
    case 5: return sv_id + 192;
    case 6: return sv_id + 64;
    default: return 255;
  }
}

Px4View read_like_px4(std::string_view bytes) {
  Px4View v;
  for (const Frame& f : test::frames_in(bytes)) {
    const std::string_view p = f.payload;
    if (f.id == MessageId{0x01, 0x35} && p.size() >= 8 && (p.size() - 8) % 12 == 0) {  // NAV-SAT
      ++v.satellite_messages;
      v.satellites.clear();
      for (std::size_t i = 0; i < get_u1(p, 5); ++i) {
        const std::size_t at = 8 + 12 * i;
        v.satellites.push_back({svinfo_number(get_u1(p, at), get_u1(p, at + 1)), int((get_u4(p, at + 8) >> 3) & 1),
                                get_u1(p, at + 2), static_cast<std::int8_t>(get_u1(p, at + 3)),
                                static_cast<std::int16_t>(get_u2(p, at + 4))});
      }
    } else if (f.id == MessageId{0x01, 0x30} && p.size() >= 8 && (p.size() - 8) % 12 == 0) {  // NAV-SVINFO
      ++v.satellite_messages;
      v.satellites.clear();
      for (std::size_t i = 0; i < get_u1(p, 4); ++i) {
        const std::size_t at = 8 + 12 * i;
        v.satellites.push_back({get_u1(p, at + 1), get_u1(p, at + 2) & 1, get_u1(p, at + 4),
                                static_cast<std::int8_t>(get_u1(p, at + 5)), static_cast<std::int16_t>(get_u2(p, at + 6))});
      }
    } else if (f.id == MessageId{0x0A, 0x09} && p.size() == 60) {  // MON-HW, u-blox 7+ layout
      v.noise_per_ms = get_u2(p, 16);
      v.automatic_gain_control = get_u2(p, 18);
      v.jamming_indicator = get_u1(p, 45);
    } else if (f.id == MessageId{0x0A, 0x38} && p.size() >= 28 && (p.size() - 4) % 24 == 0) {  // MON-RF block 0
      v.noise_per_ms = get_u2(p, 4 + 12);
      v.jamming_indicator = get_u1(p, 4 + 16);
      v.jamming_state = get_u1(p, 4 + 1);
    }
  }
  return v;
}

/// A second of solutions at 5 Hz from a u-blox port configured by what the driver wrote: a sky of
/// GPS 5 and 13, GLONASS slot 2 and Galileo 11, all but GPS 13 used.
std::string solutions_after_configuration(ReceiverModel model) {
  SessionSettings settings;
  settings.start.model = model;
  settings.start.baud = 38400;
  Session session(settings);
  session.client_wrote(g_written);
  (void)session.take_reply();
  nmea::Fix fix;
  fix.quality = nmea::FixQuality::gps;
  fix.dimension = nmea::FixDimension::three_d;
  fix.satellites_used = 3;
  fix.satellites_in_view = 4;
  fix.satellites[0] = {5, 45, 120, 42, true, nmea::GnssSystem::gps, 5};
  fix.satellites[1] = {13, 10, 300, 30, false, nmea::GnssSystem::gps, 13};
  fix.satellites[2] = {66, 33, 45, 39, true, nmea::GnssSystem::glonass, 2};
  fix.satellites[3] = {11, 60, 10, 47, true, nmea::GnssSystem::galileo, 11};
  std::string out;
  for (int k = 0; k < 5; ++k) {
    fix.time_utc = std::chrono::sys_days{std::chrono::year{2026} / 11 / 24} + std::chrono::hours{12} + k * 200ms;
    session.append_solution(epoch_of(fix), out);
  }
  return out;
}

const std::vector<Px4Satellite> px4_sky = {{5, 1, 42, 45, 120}, {13, 0, 30, 10, 300}, {66, 1, 39, 33, 45},
                                           {221, 1, 47, 60, 10}};

TEST(UbxPx4Sequence, F9pAnswersTheValsetPathAndEndsUbxOnlyAt5HzAnd115200) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_f9p);
  // 1. Protocol probe: VALSET answered means protocol 27+.
  auto got = send(m, msg::cfg_valset, uart1_valset());
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
  ASSERT_EQ(effects_of<OutputProtocolsChanged>(got.effects).size(), 1u);
  EXPECT_FALSE(effects_of<OutputProtocolsChanged>(got.effects)[0].nmea);
  // 2. Baud to 115200 (PX4 does not wait for this ACK, it reads it if it comes).
  got = send(m, msg::cfg_valset, valset({{key::uart1_baudrate, 115200}}));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
  EXPECT_EQ(effects_of<BaudChanged>(got.effects).at(0).baud, 115200u);
  // 3. MON-VER: hwVersion 00190000 and MOD=ZED-F9P make PX4 pick u_blox9_F9P_L1L2.
  got = send(m, msg::mon_ver);
  ASSERT_EQ(got.frames.size(), 1u);
  EXPECT_EQ(got.frames[0].payload.substr(30, 8), "00190000");
  EXPECT_NE(got.frames[0].payload.find("MOD=ZED-F9P"), std::string::npos);
  // 4. configureDevice(): protocols of UART1 and USB.
  got = send(m, msg::cfg_valset,
             valset({{uart1inprot_rtcm3x, 1}, {usbinprot_ubx, 1}, {usbinprot_rtcm3x, 1}, {usbinprot_nmea, 0},
                     {usboutprot_ubx, 1}, {usboutprot_nmea, 0}}));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
  // 5. Navigation settings and the measurement rate (200 ms for an F9P).
  got = send(m, msg::cfg_valset,
             valset({{key::navspg_fixmode, 3}, {navspg_utcstandard, 3}, {key::navspg_dynmodel, 7}, {odo_use_odo, 0},
                     {odo_use_cog, 0}, {odo_outlpvel, 0}, {odo_outlpcog, 0}, {key::rate_meas, 200},
                     {key::rate_nav, 1}, {key::rate_timeref, 0}}));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
  EXPECT_EQ(effects_of<MeasurementPeriodChanged>(got.effects).at(0).period, 200ms);
  // 6-8. RTK mode, jamming monitor, jamming sensitivity: each acknowledged.
  for (const std::uint32_t k : {navhpg_dgnssmode, itfm_enable, sec_jamdet_hi}) {
    got = send(m, msg::cfg_valset, valset({{k, k == navhpg_dgnssmode ? 3u : 1u}}));
    EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_valset)}) << std::hex << k;
  }
  // 9. Message rates on UART1 and USB.
  got = send(m, msg::cfg_valset,
             valset({{key::msgout_nav_pvt_i2c + uart1, 1}, {key::msgout_nav_pvt_i2c + usb, 1},
                     {msgout_hpposllh_i2c + uart1, 1}, {msgout_hpposllh_i2c + usb, 1},
                     {msgout_relposned_i2c + uart1, 0}, {msgout_relposned_i2c + usb, 0},
                     {msgout_dop_i2c + uart1, 1}, {msgout_dop_i2c + usb, 1}, {msgout_sat_i2c + uart1, 10},
                     {msgout_sat_i2c + usb, 10}, {msgout_status_i2c + uart1, 1}, {msgout_status_i2c + usb, 1},
                     {msgout_mon_rf_i2c + uart1, 1}, {msgout_mon_rf_i2c + usb, 1},
                     {msgout_rxm_rtcm_i2c + uart1, 1}, {msgout_rxm_rtcm_i2c + usb, 1}}));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
  // 10. I2C protocols.
  got = send(m, msg::cfg_valset,
             valset({{i2cinprot_ubx, 0}, {i2cinprot_nmea, 0}, {i2cinprot_rtcm3x, 0}, {i2coutprot_ubx, 0},
                     {i2coutprot_nmea, 0}, {i2coutprot_rtcm3x, 0}}));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_valset)});

  const Settings& s = m.settings();
  EXPECT_EQ(s.output_period(), 200ms);
  test::expect_solutions_every(s, m.model(), 200ms);  // the receiver's epochs: 5 Hz on the second
  EXPECT_EQ(s.dyn_model(), 7);
  EXPECT_EQ(s.ports[1].baud, 115200u);
  EXPECT_EQ(s.ports[1].out_proto_mask & proto_nmea, 0);
  EXPECT_EQ(s.rate(msg::nav_pvt, Port::uart1), 1);
  EXPECT_EQ(s.rate(msg::nav_dop, Port::uart1), 1);
  EXPECT_EQ(s.rate(msg::nav_status, Port::uart1), 1);
  EXPECT_EQ(s.rate(msg::nav_sat, Port::uart1), 10);
  EXPECT_EQ(s.rate(msg::nav_posllh, Port::uart1), 0);
  EXPECT_EQ(m.stats().naks, 0u);

  const Px4View px4 = read_like_px4(solutions_after_configuration(ReceiverModel::ublox_f9p));
  EXPECT_EQ(px4.satellite_messages, 1);  // NAV-SAT every 10th solution
  EXPECT_EQ(px4.satellites, px4_sky);
  EXPECT_EQ(px4.noise_per_ms, 89);       // MON-RF every solution
  EXPECT_EQ(px4.jamming_indicator, 9);
  EXPECT_EQ(px4.jamming_state, 1);       // ok
}

TEST(UbxPx4Sequence, M8nNaksValsetAndAnswersTheClassicPathEndingAt5HzAnd115200) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m8n);
  // 1. The VALSET probe is refused: PX4 falls back to protocol < 27.
  auto got = send(m, msg::cfg_valset, uart1_valset());
  EXPECT_EQ(got.frames, std::vector<Frame>{nak_of(msg::cfg_valset)});
  EXPECT_TRUE(got.effects.empty());
  // 2. CFG-PRT for UART1 and USB at the current baud: UBX only out.
  got = send(m, msg::cfg_prt, cfg_prt_pair(38400));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_prt)});
  EXPECT_TRUE(effects_of<BaudChanged>(got.effects).empty());
  EXPECT_FALSE(effects_of<OutputProtocolsChanged>(got.effects).at(0).nmea);
  // 3. Again with the pre-M8 baud 38400 (unchanged here), then MON-VER.
  got = send(m, msg::cfg_prt, cfg_prt_pair(38400));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_prt)});
  got = send(m, msg::mon_ver);
  ASSERT_EQ(got.frames.size(), 1u);
  EXPECT_EQ(got.frames[0].payload.substr(30, 8), "00080000");
  // 4. An M8 on auto-baud: CFG-PRT to 115200, applied after the ACK.
  got = send(m, msg::cfg_prt, cfg_prt_pair(115200));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_prt)});
  EXPECT_EQ(effects_of<BaudChanged>(got.effects).at(0).baud, 115200u);
  // 5. configureDevicePreV27(): CFG-RATE 200 ms, CFG-NAV5 (mask dyn + fix mode: airborne < 2 g, 3-D).
  got = send(m, msg::cfg_rate, test::unhex("c800 0100 0000"));
  EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_rate)});
  EXPECT_EQ(effects_of<MeasurementPeriodChanged>(got.effects).at(0).period, 200ms);
  std::string nav5(36, '\0');
  nav5[0] = 0x05;
  nav5[2] = 7;
  nav5[3] = 2;
  EXPECT_EQ(send(m, msg::cfg_nav5, nav5).frames, std::vector<Frame>{ack_of(msg::cfg_nav5)});
  // 6. Message rates, each with its ACK: PVT, STATUS, DOP, SVINFO (5: satellite info on), MON-HW.
  for (const auto& [id, rate] : std::vector<std::pair<MessageId, std::uint8_t>>{
           {msg::nav_pvt, 1}, {msg::nav_status, 1}, {msg::nav_dop, 1}, {{0x01, 0x30}, 5}, {{0x0A, 0x09}, 1}}) {
    got = send(m, msg::cfg_msg, cfg_msg_3(id, rate));
    EXPECT_EQ(got.frames, std::vector<Frame>{ack_of(msg::cfg_msg)});
  }
  const Settings& s = m.settings();
  EXPECT_EQ(s.output_period(), 200ms);
  test::expect_solutions_every(s, m.model(), 200ms);  // the receiver's epochs: 5 Hz on the second
  EXPECT_EQ(s.dyn_model(), 7);
  EXPECT_EQ(s.nav5[3], 2);
  EXPECT_EQ(s.ports[1].baud, 115200u);
  EXPECT_EQ(s.ports[3].out_proto_mask, 0x0001);
  EXPECT_EQ(s.rate(msg::nav_pvt, Port::uart1), 1);
  EXPECT_EQ(s.rate(msg::nav_status, Port::uart1), 1);
  EXPECT_EQ(s.rate(msg::nav_dop, Port::uart1), 1);
  EXPECT_EQ(m.stats().naks, 1u);

  const Px4View px4 = read_like_px4(solutions_after_configuration(ReceiverModel::ublox_m8n));
  EXPECT_EQ(px4.satellite_messages, 1);  // NAV-SVINFO every 5th solution
  EXPECT_EQ(px4.satellites, px4_sky);
  EXPECT_EQ(px4.noise_per_ms, 89);       // MON-HW every solution
  EXPECT_EQ(px4.automatic_gain_control, 3140);
  EXPECT_EQ(px4.jamming_indicator, 9);
}

// PX4-GPSDrivers src/ubx.cpp on a NEO-M9N: MON-VER without MOD=ZED-F9P makes it Board::u_blox9;
// configureDevice() then uses 125 ms (8 Hz), leaves out HPPOSLLH and RELPOSNED ("no RTCM on M9*
// except F9P") but still enables CFG-MSGOUT-UBX_RXM_RTCM_<port> in the message-rate VALSET for every
// u-blox 9 (the `_board == u_blox9 || F9P` branch), and its I2C VALSET has no I2COUTPROT_RTCM3X.
// The keys and their order are those of configure()/configureDevice() with PX4's defaults (GPS
// output mode, GPS_1_GNSS 0, no minimum C/N0 or elevation, dynamic model 7).
TEST(UbxPx4Sequence, M9nAcceptsPx4sU9ValsetWithRxmRtcmAndOutputsWhatItEnabled) {
  ConfigMachine m = machine_of(ReceiverModel::ublox_m9n);
  const std::vector<std::string> valsets = {
      uart1_valset(),
      valset({{key::uart1_baudrate, 115200}}),
      valset({{uart1inprot_rtcm3x, 1}, {usbinprot_ubx, 1}, {usbinprot_rtcm3x, 1}, {usbinprot_nmea, 0},
              {usboutprot_ubx, 1}, {usboutprot_nmea, 0}}),
      valset({{key::navspg_fixmode, 3}, {navspg_utcstandard, 3}, {key::navspg_dynmodel, 7}, {odo_use_odo, 0},
              {odo_use_cog, 0}, {odo_outlpvel, 0}, {odo_outlpcog, 0}, {key::rate_meas, 125}, {key::rate_nav, 1},
              {key::rate_timeref, 0}}),
      valset({{navhpg_dgnssmode, 3}}),
      valset({{itfm_enable, 1}}),
      valset({{sec_jamdet_hi, 1}}),
      // The message rates: the VALSET gpsemu NAKed whole before (RXM-RTCM was F9P-only).
      valset({{key::msgout_nav_pvt_i2c + uart1, 1}, {key::msgout_nav_pvt_i2c + usb, 1},
              {msgout_dop_i2c + uart1, 1}, {msgout_dop_i2c + usb, 1}, {msgout_sat_i2c + uart1, 10},
              {msgout_sat_i2c + usb, 10}, {msgout_status_i2c + uart1, 1}, {msgout_status_i2c + usb, 1},
              {msgout_mon_rf_i2c + uart1, 1}, {msgout_mon_rf_i2c + usb, 1},
              {msgout_rxm_rtcm_i2c + uart1, 1}, {msgout_rxm_rtcm_i2c + usb, 1}}),
      valset({{i2cinprot_ubx, 0}, {i2cinprot_nmea, 0}, {i2cinprot_rtcm3x, 0}, {i2coutprot_ubx, 0},
              {i2coutprot_nmea, 0}}),
  };
  for (std::size_t i = 0; i < valsets.size(); ++i) {
    if (i == 2) {  // MON-VER after the baud: no F9P, so PX4 takes it for a u-blox 9 (M9N)
      const auto ver = send(m, msg::mon_ver);
      ASSERT_EQ(ver.frames.size(), 1u);
      EXPECT_NE(ver.frames[0].payload.find("MOD=NEO-M9N"), std::string::npos);
    }
    EXPECT_EQ(send(m, msg::cfg_valset, valsets[i]).frames, std::vector<Frame>{ack_of(msg::cfg_valset)})
        << "VALSET " << i;
  }
  EXPECT_EQ(m.stats().naks, 0u);
  const Settings& s = m.settings();
  test::expect_solutions_every(s, m.model(), 125ms);
  EXPECT_EQ(s.rate(msg::nav_pvt, Port::uart1), 1);
  EXPECT_EQ(s.rate(msg::nav_status, Port::uart1), 1);
  EXPECT_EQ(s.rate(msg::mon_rf, Port::uart1), 1);
  EXPECT_EQ(s.rate(msg::rxm_rtcm, Port::uart1), 1);

  // The same bytes on a port: each solution has what PX4 enabled, and RTCM3 it forwards is reported.
  SessionSettings settings;
  settings.start.model = ReceiverModel::ublox_m9n;
  settings.start.baud = 38400;
  Session session(settings);
  session.client_wrote(g_written);
  (void)session.take_reply();
  nmea::Fix fix;
  fix.quality = nmea::FixQuality::gps;
  fix.dimension = nmea::FixDimension::three_d;
  fix.satellites_used = 8;
  std::string out;
  for (int k = 0; k < 10; ++k) {
    fix.time_utc = std::chrono::sys_days{std::chrono::year{2026} / 11 / 24} + std::chrono::hours{12} + k * 125ms;
    session.append_solution(epoch_of(fix), out);
  }
  std::map<MessageId, int> counts;
  for (const Frame& f : test::frames_in(out)) ++counts[f.id];
  EXPECT_EQ(counts[msg::nav_pvt], 10);
  EXPECT_EQ(counts[msg::nav_dop], 10);
  EXPECT_EQ(counts[msg::nav_status], 10);
  EXPECT_EQ(counts[msg::mon_rf], 10);
  EXPECT_EQ(counts[msg::nav_sat], 1);  // every 10th solution
  session.client_wrote(rtk::rtcm3_frame_bytes(rtk::encode_msm(1077, 42, 1000, 10, 2)));
  const std::vector<Frame> reports = test::frames_in(session.take_reply());
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].id, msg::rxm_rtcm);
  EXPECT_EQ(get_u2(reports[0].payload, 6), 1077);  // msgType
  EXPECT_EQ(session.take_rtcm().size(), 1u);
}

}  // namespace px4_sequence_test
}  // namespace
}  // namespace gpsemu::ubx
