// Receiver models (see model.hpp). The version strings are those real modules report.
#include "emulator/ubx/model.hpp"

#include <array>

#include "emulator/ubx/layouts.hpp"

namespace gpsemu::ubx {
namespace {

/// The u-blox identity of each row of the receiver table, in its order: protocol version, key/value
/// and legacy configuration, MON-VER's swVersion, hwVersion and extensions.
struct Identity {
  int protocol_version_x100;
  bool key_value_config;
  bool legacy_config;
  std::string_view sw_version;
  std::string_view hw_version;
  std::vector<std::string_view> extensions;
};

const std::array<Identity, kReceiverModels>& identities() {
  static const std::array<Identity, kReceiverModels> all = {
      Identity{1800, false, true, "ROM CORE 3.01 (107888)", "00080000",
               {"FWVER=SPG 3.01", "PROTVER=18.00", "GPS;GLO;GAL;BDS", "SBAS;IMES;QZSS"}},
      Identity{1800, false, true, "ROM CORE 3.01 (107888)", "00080000",
               {"FWVER=SPG 3.01", "PROTVER=18.00", "MOD=NEO-M8N-0", "GPS;GLO;GAL;BDS", "SBAS;IMES;QZSS"}},
      Identity{3201, true, true, "ROM SPG 4.04 (7f89f7)", "00190000",
               {"ROM BASE 0x118B2060", "FWVER=SPG 4.04", "PROTVER=32.01", "MOD=NEO-M9N-00B", "GPS;GLO;GAL;BDS",
                "SBAS;QZSS"}},
      Identity{2731, true, true, "EXT CORE 1.00 (61ce84)", "00190000",
               {"ROM BASE 0x118B2060", "FWVER=HPG 1.32", "PROTVER=27.31", "MOD=ZED-F9P", "GPS;GLO;GAL;BDS",
                "SBAS;QZSS"}},
      // As a MAX-M10S (SPG 5.10) reports itself; PX4 and ArduPilot detect an M10 by hwVersion 000A0000.
      Identity{3410, true, false, "ROM SPG 5.10 (7b202e)", "000A0000",
               {"ROM BASE 0x118B2060", "FWVER=SPG 5.10", "PROTVER=34.10", "MOD=MAX-M10S", "GPS;GLO;GAL;BDS",
                "SBAS;QZSS"}},
  };
  return all;
}

std::array<ModelInfo, kReceiverModels> join() {
  std::array<ModelInfo, kReceiverModels> out{};
  for (std::size_t i = 0; i < out.size(); ++i) {
    const ReceiverFacts& f = receiver_table()[i];
    const Identity& id = identities()[i];
    out[i] = ModelInfo{f.name, id.protocol_version_x100, id.key_value_config, id.legacy_config,
                       f.corrections != Corrections::none, f.default_baud, id.sw_version, id.hw_version, id.extensions};
  }
  return out;
}

}  // namespace

const ModelInfo& model_info(ReceiverModel model) {
  static const std::array<ModelInfo, kReceiverModels> all = join();
  return all[static_cast<std::size_t>(model)];
}

bool model_has_key_group(ReceiverModel model, std::uint32_t key) {
  constexpr std::uint32_t group_tmode = 0x03;
  constexpr std::uint32_t group_navhpg = 0x14;
  const std::uint32_t group = (key >> 16) & 0xFF;
  return model != ReceiverModel::ublox_m10 || (group != group_tmode && group != group_navhpg);
}

std::string mon_ver_payload(ReceiverModel model) {
  const ModelInfo& info = model_info(model);
  PayloadWriter<layout::mon_ver> w;
  w.set_text<"swVersion">(info.sw_version);
  w.set_text<"hwVersion">(info.hw_version);
  std::string p = std::move(w).bytes();
  for (const std::string_view ext : info.extensions) {
    PayloadWriter<layout::mon_ver_block> block;
    block.set_text<"extension">(ext);
    p += block.bytes();
  }
  return p;
}

}  // namespace gpsemu::ubx
