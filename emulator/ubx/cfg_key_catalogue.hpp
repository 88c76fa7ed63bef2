// The generation-9 configuration keys a u-blox receiver knows, each with its name and type
// ("CFG-RATE-MEAS", 0x30210001, U2, scale 0.001, unit s): data/ublox/config-keys.tsv (the CFG-*
// items of u-blox's interface descriptions for protocols 23 to 34, M9, F9 and X20 generations, as
// gpsd's gps/ubx.py tabulates them), compiled in. A CFG-VALSET of a key outside it is NAKed, as a
// receiver NAKs a key its configuration database does not hold; so what a client can store is
// bounded. Logs, VALGET answers and docs/ublox.md name keys from it. Pure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace gpsemu::ubx {

/// One configuration item. The type is the interface description's (L, U1, E1, X2, I4, R8...;
/// "-" for a group's wildcard key CFG-<GROUP> 0x..FFFF); its size is also in the key's bits 28-30.
struct KeyInfo {
  std::uint32_t key = 0;
  std::string_view name;   ///< "CFG-RATE-MEAS"
  std::string_view type;   ///< "U2"
  std::string_view scale;  ///< "0.001", empty for 1
  std::string_view unit;   ///< "s", empty when none
};

/// Every key, sorted by id.
[[nodiscard]] std::span<const KeyInfo> known_keys();
/// Whether `key` is a configuration item of a u-blox generation-9 receiver.
[[nodiscard]] bool is_known_key(std::uint32_t key);
/// How many keys the catalogue holds.
[[nodiscard]] std::size_t known_key_count();
/// The item of id `key`, nullptr for an unknown key.
[[nodiscard]] const KeyInfo* find_key(std::uint32_t key);
/// The item named `name` ("CFG-RATE-MEAS"), nullptr for an unknown name.
[[nodiscard]] const KeyInfo* find_key(std::string_view name);
/// The id of the key named `name`; throws std::logic_error for a name the catalogue lacks (the
/// program's own tables name keys: a misspelt name is a bug, found by the first test that runs).
[[nodiscard]] std::uint32_t key_id(std::string_view name);
/// "CFG-RATE-MEAS (0x30210001)", or "0x12345678" for an unknown key: for logs.
[[nodiscard]] std::string key_label(std::uint32_t key);

}  // namespace gpsemu::ubx
