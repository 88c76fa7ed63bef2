// Receiver models (see model.hpp). The version strings are those real modules report.
#include "emulator/ubx/model.hpp"

#include <array>

#include "emulator/ubx/layouts.hpp"

namespace gpsemu::ubx {
namespace {

const std::array<ModelInfo, 5>& models() {
  static const std::array<ModelInfo, 5> all = {
      ModelInfo{"generic", 1800, false, true, true, 9600, "ROM CORE 3.01 (107888)", "00080000",
                {"FWVER=SPG 3.01", "PROTVER=18.00", "GPS;GLO;GAL;BDS", "SBAS;IMES;QZSS"}},
      ModelInfo{"ublox-m8n", 1800, false, true, true, 9600, "ROM CORE 3.01 (107888)", "00080000",
                {"FWVER=SPG 3.01", "PROTVER=18.00", "MOD=NEO-M8N-0", "GPS;GLO;GAL;BDS", "SBAS;IMES;QZSS"}},
      ModelInfo{"ublox-m9n", 3201, true, true, true, 38400, "ROM SPG 4.04 (7f89f7)", "00190000",
                {"ROM BASE 0x118B2060", "FWVER=SPG 4.04", "PROTVER=32.01", "MOD=NEO-M9N-00B", "GPS;GLO;GAL;BDS",
                 "SBAS;QZSS"}},
      ModelInfo{"ublox-f9p", 2731, true, true, true, 38400, "EXT CORE 1.00 (61ce84)", "00190000",
                {"ROM BASE 0x118B2060", "FWVER=HPG 1.32", "PROTVER=27.31", "MOD=ZED-F9P", "GPS;GLO;GAL;BDS",
                 "SBAS;QZSS"}},
      // As a MAX-M10S (SPG 5.10) reports itself; PX4 and ArduPilot detect an M10 by hwVersion 000A0000.
      ModelInfo{"ublox-m10", 3410, true, false, false, 9600, "ROM SPG 5.10 (7b202e)", "000A0000",
                {"ROM BASE 0x118B2060", "FWVER=SPG 5.10", "PROTVER=34.10", "MOD=MAX-M10S", "GPS;GLO;GAL;BDS",
                 "SBAS;QZSS"}},
  };
  return all;
}

}  // namespace

const ModelInfo& model_info(ReceiverModel model) { return models()[static_cast<std::size_t>(model)]; }

std::optional<ReceiverModel> receiver_model_from_name(std::string_view name) {
  for (std::size_t i = 0; i < models().size(); ++i) {
    if (models()[i].name == name) return static_cast<ReceiverModel>(i);
  }
  return std::nullopt;
}

bool dual_band(ReceiverModel model) { return model == ReceiverModel::ublox_f9p; }

bool dgnss_only(ReceiverModel model) { return model == ReceiverModel::ublox_m9n; }

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
