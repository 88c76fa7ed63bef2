// The u-blox receiver models gpsemu can be (--receiver): what each answers to MON-VER, which
// configuration interface it speaks (M8: protocol 18-23, CFG-* messages only; M9/F9: 27+, the
// key/value interface CFG-VALSET/VALGET/VALDEL beside the deprecated CFG-* messages; M10 SPG 5.10,
// protocol 34.10: CFG-VALSET/VALGET/VALDEL, CFG-CFG and CFG-RST only) and its default baud rate.
// `generic` answers as an M8 does. Which messages each has: messages.hpp. Pure values.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/ubx/frame.hpp"

namespace gpsemu::ubx {

enum class ReceiverModel { generic, ublox_m8n, ublox_m9n, ublox_f9p, ublox_m10 };

struct ModelInfo {
  std::string_view name;          ///< "ublox-m8n" (the --receiver value)
  int protocol_version_x100 = 0;  ///< PROTVER times 100: 1800 is 18.00
  bool key_value_config = false;  ///< answers CFG-VALSET/VALGET/VALDEL (protocol 27+)
  bool legacy_config = true;      ///< takes the CFG-* messages beside CFG-VAL* (not the M10: VALSET only)
  bool rtcm_input = true;         ///< its ports use RTCM3 corrections (not the M10, SPG 5.10: ignored)
  std::uint32_t default_baud = 0; ///< UART1 baud after a factory reset (bits per second)
  std::string_view sw_version;    ///< MON-VER swVersion (30 characters at most)
  std::string_view hw_version;    ///< MON-VER hwVersion: "00080000" M8, "00190000" M9/F9
  std::vector<std::string_view> extensions;  ///< MON-VER extension strings (30 characters each)
};

[[nodiscard]] const ModelInfo& model_info(ReceiverModel model);
/// The model named `name` ("ublox-f9p"), nullopt for an unknown name.
[[nodiscard]] std::optional<ReceiverModel> receiver_model_from_name(std::string_view name);
/// Whether `model` tracks a second band (L2/E5b/B2I): the F9P.
[[nodiscard]] bool dual_band(ReceiverModel model);
/// Whether `model` uses RTCM3 corrections for DGNSS only, never RTK float/fixed: the M9N (SPG
/// firmware; carrier-phase RTK is the F9P's HPG firmware).
[[nodiscard]] bool dgnss_only(ReceiverModel model);
/// Whether `model`'s firmware has the configuration key `key` (by its group, bits 16-23): the M10's
/// standard-precision firmware (SPG 5.10) has no CFG-NAVHPG (high-precision navigation: RTK) and no
/// CFG-TMODE (a base's time mode) group, so a VALSET or VALGET naming one of their keys is NAKed
/// whole, as for any key a firmware does not know (PX4 writes CFG-NAVHPG-DGNSSMODE to every
/// u-blox 9+ and takes the NAK of a receiver without RTK). Message keys: model_has_message().
[[nodiscard]] bool model_has_key_group(ReceiverModel model, std::uint32_t key);
/// MON-VER's payload for `model`: swVersion[30], hwVersion[10], extension[30] each.
[[nodiscard]] std::string mon_ver_payload(ReceiverModel model);

}  // namespace gpsemu::ubx
