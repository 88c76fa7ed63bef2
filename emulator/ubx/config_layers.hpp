// Where a u-blox keeps its configuration (the interface description's "configuration layers"):
// RAM (the settings in use, settings.hpp), BBR (battery-backed RAM) and flash, and the defaults.
// At power-up and after a hardware or controlled software reset (CFG-RST) RAM is built from the
// defaults, then what flash holds, then what BBR holds (each layer overrides the one below).
// CFG-VALSET writes keys into any of RAM, BBR and flash, CFG-VALDEL deletes keys from BBR and
// flash, CFG-VALGET reads one layer; CFG-CFG clears a stored layer, saves RAM into it, or loads RAM
// from the stored layers. A stored layer holds keys (generation-9 items) and, for the classic
// messages of an M8, the blocks without keys (CFG-NAV5, CFG-GNSS, CFG-SBAS) and the rates of
// messages without a CFG-MSGOUT key. The emulator's start settings are the defaults; the stored
// layers can be kept across runs as text (--receiver-state). Pure.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "emulator/ubx/model.hpp"
#include "emulator/ubx/settings.hpp"

namespace gpsemu::ubx {

/// CFG-VALSET / CFG-VALDEL layer bits.
inline constexpr std::uint8_t layer_bit_ram = 0x01;
inline constexpr std::uint8_t layer_bit_bbr = 0x02;
inline constexpr std::uint8_t layer_bit_flash = 0x04;
/// CFG-VALGET layer numbers.
inline constexpr std::uint8_t layer_ram = 0;
inline constexpr std::uint8_t layer_bbr = 1;
inline constexpr std::uint8_t layer_flash = 2;
inline constexpr std::uint8_t layer_default = 7;

/// What BBR or flash holds.
struct StoredLayer {
  std::map<std::uint32_t, std::uint64_t> keys;     ///< generation-9 items saved in the layer
  std::map<MessageId, PortRates> keyless_rates;    ///< CFG-MSG rates of messages without a key
  std::optional<std::string> nav5, gnss, sbas;     ///< classic blocks (CFG-CFG save)

  [[nodiscard]] bool empty() const { return keys.empty() && keyless_rates.empty() && !nav5 && !gnss && !sbas; }
  friend bool operator==(const StoredLayer&, const StoredLayer&) = default;
};

/// The two non-volatile layers.
struct StoredLayers {
  StoredLayer bbr;
  StoredLayer flash;
  friend bool operator==(const StoredLayers&, const StoredLayers&) = default;
};

/// Everything RAM holds, as CFG-CFG save writes it into a layer.
[[nodiscard]] StoredLayer snapshot(const Settings& s);
/// Writes what `layer` holds over `s` (blocks first, then the keys).
void apply_layer(Settings& s, const StoredLayer& layer);
/// RAM at power-up: `defaults`, then flash, then BBR.
[[nodiscard]] Settings power_up(const Settings& defaults, const StoredLayers& layers);

/// The stored layers as text (one item a line), for --receiver-state.
[[nodiscard]] std::string to_text(const StoredLayers& layers, ReceiverModel model);
/// Reads to_text()'s text back. Throws std::invalid_argument naming the line for a malformed one,
/// or when the state was saved by another receiver model.
[[nodiscard]] StoredLayers stored_layers_from_text(std::string_view text, ReceiverModel model);

}  // namespace gpsemu::ubx
