// The configuration layers as a client sees them through the state machine (ubx/config_layers.hpp,
// ubx/machine.hpp): CFG-CFG save/load/clear, CFG-VALSET to RAM, BBR and flash with and without
// transactions, CFG-VALDEL, CFG-VALGET of each layer, CFG-RST reloading RAM from the layers,
// unknown keys and invalid layers or transaction codes NAKed, the port's output mask obeyed, and
// the stored layers as text (--receiver-state) and back.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "emulator/ubx/cfg_key_catalogue.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/config_layers.hpp"
#include "emulator/ubx/machine.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace config_layers_test {

using namespace std::chrono_literals;
using test::ack_of;
using test::effects_of;
using test::nak_of;
using test::send;
using test::valget;
using test::valset;

ConfigMachine f9p(StoredLayers stored = {}) {
  StartSettings start;
  start.model = ReceiverModel::ublox_f9p;
  return ConfigMachine(start, std::move(stored));
}

std::string cfg_rate(std::uint16_t ms) {
  std::string p;
  put_u2(p, ms);
  put_u2(p, 1);
  put_u2(p, 1);
  return p;
}

/// CFG-CFG: clear, save, load masks (and a device mask when given).
std::string cfg_cfg(std::uint32_t clear, std::uint32_t save, std::uint32_t load, int devices = -1) {
  std::string p;
  put_u4(p, clear);
  put_u4(p, save);
  put_u4(p, load);
  if (devices >= 0) put_u1(p, static_cast<std::uint32_t>(devices));
  return p;
}

/// CFG-RST with `reset_mode` (0 hardware reset, 1 controlled software reset, 2 GNSS only).
std::string cfg_rst(std::uint8_t reset_mode, std::uint16_t nav_bbr = 0) {
  std::string p;
  put_u2(p, nav_bbr);
  put_u1(p, reset_mode);
  put_u1(p, 0);
  return p;
}

/// A VALSET of version 1 with a transaction code.
std::string valset_tx(std::initializer_list<test::KeyValue> items, std::uint8_t transaction, std::uint8_t layers = 1) {
  std::string p = valset(items, layers);
  p[0] = 1;
  p[2] = static_cast<char>(transaction);
  return p;
}

std::uint64_t ram_value(ConfigMachine& m, std::uint32_t key, std::uint8_t layer = layer_ram) {
  const auto got = send(m, msg::cfg_valget, valget({key}, layer));
  if (got.frames.size() != 2 || got.frames[0].id != msg::cfg_valget || got.frames[0].payload.size() < 9) return 0xDEAD;
  return get_le(got.frames[0].payload, 8, static_cast<int>(key_value_bytes(key)));
}

TEST(UbxConfigLayers, CfgCfgSaveThenLoadBringsBackWhatWasSavedNotTheStartDefaults) {
  ConfigMachine m = f9p();
  ASSERT_EQ(send(m, msg::cfg_rate, cfg_rate(200)).frames, std::vector<Frame>{ack_of(msg::cfg_rate)});
  EXPECT_EQ(send(m, msg::cfg_cfg, cfg_cfg(0, 0xFFFF, 0)).frames, std::vector<Frame>{ack_of(msg::cfg_cfg)});
  (void)send(m, msg::cfg_rate, cfg_rate(1000));
  const auto loaded = send(m, msg::cfg_cfg, cfg_cfg(0, 0, 0xFFFF));
  EXPECT_EQ(loaded.frames, std::vector<Frame>{ack_of(msg::cfg_cfg)});
  ASSERT_EQ(effects_of<MeasurementPeriodChanged>(loaded.effects).size(), 1u);
  EXPECT_EQ(effects_of<MeasurementPeriodChanged>(loaded.effects)[0].period, 200ms);
  EXPECT_EQ(m.settings().meas_period_ms, 200);
  // Clear, then load: the defaults again.
  (void)send(m, msg::cfg_cfg, cfg_cfg(0xFFFF, 0, 0xFFFF));
  EXPECT_EQ(m.settings().meas_period_ms, 1000);
  EXPECT_TRUE(m.stored().bbr.empty());
  EXPECT_TRUE(m.stored().flash.empty());
}

TEST(UbxConfigLayers, CfgCfgDeviceMaskPicksTheLayer) {
  ConfigMachine m = f9p();
  (void)send(m, msg::cfg_rate, cfg_rate(250));
  (void)send(m, msg::cfg_cfg, cfg_cfg(0, 0xFFFF, 0, 0x02));  // flash only
  EXPECT_TRUE(m.stored().bbr.empty());
  EXPECT_EQ(m.stored().flash.keys.at(key::rate_meas), 250u);
  EXPECT_EQ(ram_value(m, key::rate_meas, layer_flash), 250u);
  EXPECT_EQ(send(m, msg::cfg_valget, valget({key::rate_meas}, layer_bbr)).frames, std::vector<Frame>{nak_of(msg::cfg_valget)});
}

TEST(UbxConfigLayers, AHardwareResetReloadsRamFromTheLayersAndAGnssResetKeepsIt) {
  ConfigMachine m = f9p();
  (void)send(m, msg::cfg_valset, valset({{key::rate_meas, 200}}));                                    // RAM
  (void)send(m, msg::cfg_valset, valset({{key::navspg_dynmodel, 8}}, layer_bit_bbr | layer_bit_flash));  // stored
  EXPECT_EQ(m.settings().dyn_model(), 0);  // stored only: not in use yet
  auto got = send(m, msg::cfg_rst, cfg_rst(0x02));  // GNSS only: RAM stays
  EXPECT_TRUE(got.frames.empty());
  EXPECT_EQ(m.settings().meas_period_ms, 200);
  got = send(m, msg::cfg_rst, cfg_rst(0x00));  // hardware reset
  EXPECT_TRUE(got.frames.empty()) << "CFG-RST is never acknowledged";
  EXPECT_EQ(m.settings().meas_period_ms, 1000);
  EXPECT_EQ(m.settings().dyn_model(), 8);
  ASSERT_EQ(effects_of<MeasurementPeriodChanged>(got.effects).size(), 1u);
  EXPECT_EQ(effects_of<MeasurementPeriodChanged>(got.effects)[0].period, 1000ms);
  EXPECT_EQ(m.stats().resets, 1u);
  // VALDEL from BBR: flash still holds it; from both: the default after the next reset.
  std::string del;
  put_u1(del, 0);
  put_u1(del, layer_bit_bbr);
  put_zeros(del, 2);
  put_u4(del, key::navspg_dynmodel);
  EXPECT_EQ(send(m, msg::cfg_valdel, del).frames, std::vector<Frame>{ack_of(msg::cfg_valdel)});
  (void)send(m, msg::cfg_rst, cfg_rst(0x01));
  EXPECT_EQ(m.settings().dyn_model(), 8);
  del[1] = static_cast<char>(layer_bit_flash);
  (void)send(m, msg::cfg_valdel, del);
  (void)send(m, msg::cfg_rst, cfg_rst(0x01));
  EXPECT_EQ(m.settings().dyn_model(), 0);
  del[1] = static_cast<char>(layer_bit_ram);  // RAM is no layer to delete from
  EXPECT_EQ(send(m, msg::cfg_valdel, del).frames, std::vector<Frame>{nak_of(msg::cfg_valdel)});
}

TEST(UbxConfigLayers, BbrOverridesFlashAtPowerUp) {
  StoredLayers stored;
  stored.flash.keys[key::rate_meas] = 500;
  stored.flash.keys[key::navspg_dynmodel] = 6;
  stored.bbr.keys[key::rate_meas] = 250;
  ConfigMachine m = f9p(stored);
  EXPECT_EQ(m.settings().meas_period_ms, 250);
  EXPECT_EQ(m.settings().dyn_model(), 6);
  EXPECT_EQ(ram_value(m, key::rate_meas, layer_default), 1000u);
  EXPECT_EQ(ram_value(m, key::rate_meas, layer_bbr), 250u);
  EXPECT_EQ(ram_value(m, key::rate_meas, layer_flash), 500u);
}

TEST(UbxConfigLayers, ATransactionAppliesOnlyAtItsApplyAndIsDiscardedOtherwise) {
  ConfigMachine m = f9p();
  // Begin, continue: acknowledged, nothing in use yet.
  EXPECT_EQ(send(m, msg::cfg_valset, valset_tx({{key::rate_meas, 200}}, 1)).frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
  EXPECT_EQ(send(m, msg::cfg_valset, valset_tx({{key::navspg_dynmodel, 4}}, 2)).frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
  EXPECT_EQ(m.settings().meas_period_ms, 1000);
  EXPECT_TRUE(m.transaction_open());
  const auto applied = send(m, msg::cfg_valset, valset_tx({}, 3));
  EXPECT_EQ(applied.frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
  EXPECT_EQ(m.settings().meas_period_ms, 200);
  EXPECT_EQ(m.settings().dyn_model(), 4);
  EXPECT_EQ(effects_of<MeasurementPeriodChanged>(applied.effects).size(), 1u);
  // A begin never applied: gone when a VALSET outside it comes, and counted.
  (void)send(m, msg::cfg_valset, valset_tx({{key::rate_meas, 500}}, 1));
  (void)send(m, msg::cfg_valset, valset({{key::navspg_dynmodel, 6}}));
  EXPECT_FALSE(m.transaction_open());
  EXPECT_EQ(m.settings().meas_period_ms, 200);
  EXPECT_EQ(m.stats().transactions_discarded, 1u);
  // Continue or apply without a begin, another layer than the begin's, code 7: NAK.
  EXPECT_EQ(send(m, msg::cfg_valset, valset_tx({{key::rate_meas, 500}}, 2)).frames, std::vector<Frame>{nak_of(msg::cfg_valset)});
  EXPECT_EQ(send(m, msg::cfg_valset, valset_tx({}, 3)).frames, std::vector<Frame>{nak_of(msg::cfg_valset)});
  (void)send(m, msg::cfg_valset, valset_tx({{key::rate_meas, 500}}, 1));
  EXPECT_EQ(send(m, msg::cfg_valset, valset_tx({}, 3, layer_bit_bbr)).frames, std::vector<Frame>{nak_of(msg::cfg_valset)});
  EXPECT_EQ(send(m, msg::cfg_valset, valset_tx({{key::rate_meas, 500}}, 7)).frames, std::vector<Frame>{nak_of(msg::cfg_valset)});
  EXPECT_EQ(m.settings().meas_period_ms, 200);
  // The client went away with a transaction open: discarded.
  (void)send(m, msg::cfg_valset, valset_tx({{key::rate_meas, 500}}, 1));
  m.discard_transaction();
  EXPECT_EQ(send(m, msg::cfg_valset, valset_tx({}, 3)).frames, std::vector<Frame>{nak_of(msg::cfg_valset)});
  EXPECT_EQ(m.settings().meas_period_ms, 200);
}

TEST(UbxConfigLayers, InvalidLayersAndUnknownKeysAreNakedAndNothingIsStored) {
  ConfigMachine m = f9p();
  EXPECT_EQ(send(m, msg::cfg_valset, valset({{key::rate_meas, 200}}, 0)).frames, std::vector<Frame>{nak_of(msg::cfg_valset)});
  EXPECT_EQ(send(m, msg::cfg_valset, valset({{key::rate_meas, 200}}, 0x09)).frames, std::vector<Frame>{nak_of(msg::cfg_valset)});
  EXPECT_EQ(send(m, msg::cfg_valget, valget({key::rate_meas}, 0x55)).frames, std::vector<Frame>{nak_of(msg::cfg_valget)});
  EXPECT_EQ(send(m, msg::cfg_valget, valget({key::rate_meas}, 3)).frames, std::vector<Frame>{nak_of(msg::cfg_valget)});
  // A key no receiver knows, in one message with a good one: the whole message is NAKed.
  const std::uint32_t unknown = 0x30FE0001;
  ASSERT_FALSE(is_known_key(unknown));
  EXPECT_EQ(send(m, msg::cfg_valset, valset({{key::rate_meas, 200}, {unknown, 5}})).frames,
            std::vector<Frame>{nak_of(msg::cfg_valset)});
  EXPECT_EQ(m.settings().meas_period_ms, 1000);
  EXPECT_EQ(send(m, msg::cfg_valget, valget({unknown})).frames, std::vector<Frame>{nak_of(msg::cfg_valget)});
  // 10 000 distinct unknown keys store nothing: what a client can store is the catalogue.
  for (std::uint32_t k = 0; k < 10000; ++k) (void)send(m, msg::cfg_valset, valset({{0x10FE0000 + k, 1}}));
  EXPECT_LE(m.settings().other_keys.size(), known_key_count());
  EXPECT_LT(m.settings().other_keys.size(), 64u);
}

TEST(UbxConfigLayers, APortWhoseOutputExcludesUbxGetsNoAnswerAndTheSkippedAnswersAreCounted) {
  ConfigMachine m = f9p();
  // UART1 (the client's port) outputs neither UBX nor NMEA: the ACK of this very write is not sent.
  EXPECT_TRUE(send(m, msg::cfg_valset, valset({{key::uart1outprot_ubx, 0}, {key::uart1outprot_nmea, 0}})).frames.empty());
  EXPECT_TRUE(send(m, msg::mon_ver).frames.empty());
  EXPECT_TRUE(send(m, msg::cfg_rate).frames.empty());
  EXPECT_EQ(m.stats().unsent_answers, 4u);  // ACK; MON-VER; CFG-RATE and its ACK
  // UBX output back on (the input still takes UBX): answered again.
  EXPECT_EQ(send(m, msg::cfg_valset, valset({{key::uart1outprot_ubx, 1}})).frames, std::vector<Frame>{ack_of(msg::cfg_valset)});
}

TEST(UbxConfigLayers, ACfgMsgComparesOnlyTheMessageItNames) {
  ConfigMachine m = f9p();
  const std::string one{static_cast<char>(0x01), static_cast<char>(0x07), static_cast<char>(1)};
  const auto got = send(m, msg::cfg_msg, one);
  ASSERT_EQ(got.effects.size(), 1u);
  EXPECT_EQ(effects_of<MessageRateChanged>(got.effects)[0].id, msg::nav_pvt);
  EXPECT_TRUE(send(m, msg::cfg_msg, one).effects.empty()) << "the same rate again changes nothing";
}

TEST(UbxConfigLayers, StoredLayersGoToTextAndBack) {
  ConfigMachine m = f9p();
  (void)send(m, msg::cfg_rate, cfg_rate(200));
  (void)send(m, msg::cfg_cfg, cfg_cfg(0, 0xFFFF, 0, 0x01));  // BBR: everything, blocks too
  (void)send(m, msg::cfg_valset, valset({{key::navspg_dynmodel, 7}}, layer_bit_flash));
  const std::string text = to_text(m.stored(), ReceiverModel::ublox_f9p);
  EXPECT_EQ(stored_layers_from_text(text, ReceiverModel::ublox_f9p), m.stored());
  EXPECT_NE(text.find("flash key 20110021 7"), std::string::npos) << text;
  // Another model's state, a malformed line, no header: refused with the line.
  EXPECT_THROW((void)stored_layers_from_text(text, ReceiverModel::ublox_m8n), std::invalid_argument);
  try {
    (void)stored_layers_from_text(text + "bbr key zz 1\n", ReceiverModel::ublox_f9p);
    FAIL() << "accepted a bad key";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("line "), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)stored_layers_from_text("bbr key 30210001 c8\n", ReceiverModel::ublox_f9p), std::invalid_argument);
  EXPECT_THROW((void)stored_layers_from_text(text + "bbr key 30fe0001 1\n", ReceiverModel::ublox_f9p),
               std::invalid_argument)
      << "a key no u-blox has";
  // Read back, the layers make the same receiver.
  ConfigMachine again = f9p(stored_layers_from_text(text, ReceiverModel::ublox_f9p));
  EXPECT_EQ(again.settings().meas_period_ms, 200);
  EXPECT_EQ(again.settings().dyn_model(), 0) << "BBR's saved dynModel 0 overrides flash's 7";
}

TEST(UbxConfigLayers, AnM8SavesAndLoadsTheClassicBlocksAndRatesWithoutKeys) {
  StartSettings start;
  start.model = ReceiverModel::ublox_m8n;
  ConfigMachine m(start);
  const std::string svinfo{static_cast<char>(0x01), static_cast<char>(0x30), static_cast<char>(5)};  // no CFG-MSGOUT key
  (void)send(m, msg::cfg_msg, svinfo);
  (void)send(m, msg::cfg_cfg, cfg_cfg(0, 0xFFFF, 0));
  (void)send(m, msg::cfg_rst, cfg_rst(0x00));
  EXPECT_EQ(m.settings().rate({0x01, 0x30}, Port::uart1), 5);
  EXPECT_EQ(send(m, msg::cfg_valset, valset({{key::rate_meas, 200}})).frames, std::vector<Frame>{nak_of(msg::cfg_valset)})
      << "an M8 has no CFG-VALSET";
}

}  // namespace config_layers_test
}  // namespace
}  // namespace gpsemu::ubx
