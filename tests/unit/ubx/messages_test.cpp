// The message table and the key catalogue (messages.hpp, cfg_key_catalogue.hpp): the CFG-MSGOUT
// keys found by name are the interface descriptions' ids, each encoder's payload has its layout's
// size, each model has the messages its interface description lists, and keys have their names.
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "emulator/ubx/cfg_key_catalogue.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/messages.hpp"

namespace gpsemu::ubx {
namespace {
namespace messages_test {

TEST(UbxMessages, MsgoutKeysFoundByNameAreTheInterfaceDescriptionsIds) {
  // The I2C key of each message (u-blox F9 HPG 1.32 / M9 SPG 4.04 interface descriptions); UART1,
  // UART2, USB and SPI follow it at +1..+4.
  const std::pair<MessageId, std::uint32_t> expected[] = {
      {msg::nav_sol, 0x20910001},     {msg::nav_svinfo, 0x2091000B},   {msg::nav_sbas, 0x2091006A},
      {msg::nav_pvt, 0x20910006},     {msg::nav_posllh, 0x20910029},   {msg::nav_velned, 0x20910042},
      {msg::nav_status, 0x2091001A},  {msg::nav_dop, 0x20910038},      {msg::nav_sat, 0x20910015},
      {msg::nav_timeutc, 0x2091005B}, {msg::nav_timegps, 0x20910047},  {msg::nav_cov, 0x20910083},
      {msg::nav_posecef, 0x20910024}, {msg::nav_velecef, 0x2091003D},  {msg::nav_hpposllh, 0x20910033},
      {msg::nav_clock, 0x20910065},   {msg::nav_timels, 0x20910060},   {msg::nav_svin, 0x20910088},
      {msg::nav_relposned, 0x2091008D}, {msg::nav_sig, 0x20910345},    {msg::nav_eoe, 0x2091015F},
      {{0x02, 0x13}, 0x20910231},     {{0x02, 0x15}, 0x209102A4},      {msg::rxm_rtcm, 0x20910268},
      {msg::mon_hw, 0x209101B4},      {msg::mon_hw2, 0x209101B9},      {msg::mon_rf, 0x20910359},
      {{0xF0, 0x00}, 0x209100BA},     {{0xF0, 0x01}, 0x209100C9},      {{0xF0, 0x02}, 0x209100BF},
      {{0xF0, 0x03}, 0x209100C4},     {{0xF0, 0x04}, 0x209100AB},      {{0xF0, 0x05}, 0x209100B0},
      {{0xF0, 0x06}, 0x209100CE},     {{0xF0, 0x07}, 0x209100D3},      {{0xF0, 0x08}, 0x209100D8},
      {{0xF0, 0x09}, 0x209100DD},     {{0xF0, 0x0A}, 0x209100A6},      {{0xF0, 0x0D}, 0x209100B5},
      {{0xF0, 0x0F}, 0x209100E7},
  };
  std::size_t with_keys = 0;
  for (const MessageRow& row : message_table()) with_keys += row.msgout ? 1 : 0;
  EXPECT_EQ(with_keys, std::size(expected));
  for (const auto& [id, i2c] : expected) {
    for (std::uint32_t port = 0; port < 5; ++port) {
      EXPECT_EQ(msgout_key(id, static_cast<Port>(port)), i2c + port) << message_name(id) << " port " << port;
      const auto back = msgout_of(i2c + port);
      ASSERT_TRUE(back.has_value()) << message_name(id);
      EXPECT_EQ(back->first, id);
      EXPECT_EQ(back->second, static_cast<Port>(port));
    }
  }
  EXPECT_EQ(msgout_key(msg::mon_ver, Port::uart1), std::nullopt);
  EXPECT_EQ(msgout_of(key::rate_meas), std::nullopt);
}

TEST(UbxMessages, EachEncoderWritesItsLayoutsSize) {
  nmea::Fix fix;
  fix.satellites_in_view = 3;
  for (int i = 0; i < 3; ++i) {
    fix.satellites[static_cast<std::size_t>(i)].prn = i + 1;
    fix.satellites[static_cast<std::size_t>(i)].snr_dbhz = 40;
  }
  NavExtras extras;
  extras.model = ReceiverModel::ublox_m9n;  // single band: one NAV-SIG signal and one MON-RF block each
  for (const MessageRow& row : message_table()) {
    if (row.encode == nullptr) continue;
    ASSERT_FALSE(row.fields.empty()) << row.name;
    const std::size_t blocks = row.block.empty() ? 0 : row.id == msg::mon_rf ? 1 : 3;
    EXPECT_EQ(row.encode(fix, extras).size(), layout_bytes(row.fields) + blocks * layout_bytes(row.block)) << row.name;
  }
}

TEST(UbxMessages, EachModelHasTheMessagesOfItsInterfaceDescription) {
  using M = ReceiverModel;
  for (const M m : {M::generic, M::ublox_m8n}) {
    EXPECT_TRUE(model_has_message(m, msg::nav_svinfo));
    EXPECT_TRUE(model_has_message(m, msg::nav_sbas));
    for (const MessageId id : {msg::nav_sig, msg::mon_rf, msg::rxm_rtcm, msg::nav_hpposllh, msg::nav_relposned,
                               msg::nav_svin, msg::cfg_valset, msg::cfg_valget, msg::cfg_valdel}) {
      EXPECT_FALSE(model_has_message(m, id)) << message_name(id);
    }
  }
  // NAV-SVINFO and NAV-SBAS were removed in protocol 27; the M9N takes RTCM3 (DGNSS) and reports it.
  EXPECT_FALSE(model_has_message(M::ublox_m9n, msg::nav_svinfo));
  EXPECT_FALSE(model_has_message(M::ublox_m9n, msg::nav_sbas));
  EXPECT_TRUE(model_has_message(M::ublox_m9n, msg::rxm_rtcm));
  EXPECT_TRUE(model_has_message(M::ublox_m9n, msg::nav_sig));
  EXPECT_FALSE(model_has_message(M::ublox_m9n, msg::nav_relposned));
  EXPECT_TRUE(model_has_message(M::ublox_f9p, msg::nav_relposned));
  EXPECT_TRUE(model_has_message(M::ublox_f9p, msg::nav_hpposllh));
  EXPECT_TRUE(model_has_message(M::ublox_f9p, {0x27, 0x03}));  // not in the table: not modelled per model
}

TEST(UbxMessages, NamesAndIdsRoundTrip) {
  std::set<std::string_view> names;
  for (const MessageRow& row : message_table()) {
    EXPECT_TRUE(names.insert(row.name).second) << row.name;
    EXPECT_EQ(find_message(row.name), &row);
    EXPECT_EQ(find_message(row.id), &row);
  }
  EXPECT_EQ(message_name({0x01, 0x99}), "0x01-0x99");
}

TEST(UbxKeyCatalogue, KeysHaveTheirNamesTypesAndUnits) {
  EXPECT_EQ(known_key_count(), 1365u);
  const KeyInfo* meas = find_key(key::rate_meas);
  ASSERT_NE(meas, nullptr);
  EXPECT_EQ(meas->name, "CFG-RATE-MEAS");
  EXPECT_EQ(meas->type, "U2");
  EXPECT_EQ(meas->scale, "0.001");
  EXPECT_EQ(meas->unit, "s");
  EXPECT_EQ(key_id("CFG-RATE-NAV"), key::rate_nav);
  EXPECT_EQ(key_id("CFG-RATE-TIMEREF"), key::rate_timeref);
  EXPECT_EQ(key_id("CFG-UART1-BAUDRATE"), key::uart1_baudrate);
  EXPECT_EQ(key_id("CFG-UART2-BAUDRATE"), key::uart2_baudrate);
  EXPECT_EQ(key_id("CFG-UART1INPROT-UBX"), key::uart1inprot_ubx);
  EXPECT_EQ(key_id("CFG-UART1OUTPROT-UBX"), key::uart1outprot_ubx);
  EXPECT_EQ(key_id("CFG-UART1OUTPROT-NMEA"), key::uart1outprot_nmea);
  EXPECT_EQ(key_id("CFG-NAVSPG-FIXMODE"), key::navspg_fixmode);
  EXPECT_EQ(key_id("CFG-NAVSPG-DYNMODEL"), key::navspg_dynmodel);
  EXPECT_EQ(key_id("CFG-MSGOUT-UBX_RXM_RTCM_UART1"), 0x20910269u);  // docs/rtk.md's key
  EXPECT_EQ(key_label(0x20910007), "CFG-MSGOUT-UBX_NAV_PVT_UART1 (0x20910007)");
  EXPECT_EQ(key_label(0x30990001), "0x30990001");
  EXPECT_THROW((void)key_id("CFG-NO-SUCH"), std::logic_error);
  // Every key's type has the size its id's bits 28-30 say (a 1-bit L takes one byte).
  for (const KeyInfo& k : known_keys()) {
    if (k.type == "-") continue;
    const std::size_t bytes = k.type == "L" ? 1 : static_cast<std::size_t>(k.type[1] - '0');
    EXPECT_EQ(bytes, key_value_bytes(k.key)) << k.name;
  }
}

}  // namespace messages_test
}  // namespace
}  // namespace gpsemu::ubx
