// The u-blox identity of each receiver model (--receiver; its facts below any protocol are in the
// receiver table, emulator/model/receiver_models.hpp): what each answers to MON-VER, which
// configuration interface it speaks (M8: protocol 18-23, CFG-* messages only; M9/F9: 27+, the
// key/value interface CFG-VALSET/VALGET/VALDEL beside the deprecated CFG-* messages; M10 SPG 5.10,
// protocol 34.10: CFG-VALSET/VALGET/VALDEL, CFG-CFG and CFG-RST only). `generic` answers as an
// M8 does. Which messages each has: messages.hpp. Pure values.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/model/receiver_models.hpp"
#include "emulator/ubx/frame.hpp"

namespace gpsemu::ubx {

using ReceiverModel = gpsemu::ReceiverModel;

struct ModelInfo {
  std::string_view name;          ///< the row's name in the receiver table ("ublox-m8n")
  int protocol_version_x100 = 0;  ///< PROTVER times 100: 1800 is 18.00
  bool key_value_config = false;  ///< answers CFG-VALSET/VALGET/VALDEL (protocol 27+)
  bool legacy_config = true;      ///< takes the CFG-* messages beside CFG-VAL* (not the M10: VALSET only)
  bool rtcm_input = true;         ///< its ports take RTCM3 (the table's corrections are not none)
  std::uint32_t default_baud = 0; ///< UART1 baud after a factory reset (the table's)
  std::string_view sw_version;    ///< MON-VER swVersion (30 characters at most)
  std::string_view hw_version;    ///< MON-VER hwVersion: "00080000" M8, "00190000" M9/F9
  std::vector<std::string_view> extensions;  ///< MON-VER extension strings (30 characters each)
};

[[nodiscard]] const ModelInfo& model_info(ReceiverModel model);
/// Whether `model` tracks a second band (L2/E5b/B2I): the table's tracking.dual_band.
[[nodiscard]] inline bool dual_band(ReceiverModel model) { return facts_of(model).tracking.dual_band; }
/// Whether `model`'s firmware has the configuration key `key` (by its group, bits 16-23): the M10's
/// standard-precision firmware (SPG 5.10) has no CFG-NAVHPG (high-precision navigation: RTK) and no
/// CFG-TMODE (a base's time mode) group, so a VALSET or VALGET naming one of their keys is NAKed
/// whole, as for any key a firmware does not know (PX4 writes CFG-NAVHPG-DGNSSMODE to every
/// u-blox 9+ and takes the NAK of a receiver without RTK). Message keys: model_has_message().
[[nodiscard]] bool model_has_key_group(ReceiverModel model, std::uint32_t key);
/// MON-VER's payload for `model`: swVersion[30], hwVersion[10], extension[30] each.
[[nodiscard]] std::string mon_ver_payload(ReceiverModel model);

}  // namespace gpsemu::ubx
