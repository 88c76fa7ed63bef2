// Which generation-9 configuration keys exist (cfg_key_catalogue.cpp): a CFG-VALSET of any other
// key is NAKed, as on a receiver, so what a client can store is bounded. Pure.
#pragma once

#include <cstddef>
#include <cstdint>

namespace gpsemu::ubx {

/// Whether `key` is a configuration item of a u-blox generation-9 receiver.
[[nodiscard]] bool is_known_key(std::uint32_t key);
/// How many keys the catalogue holds.
[[nodiscard]] std::size_t known_key_count();

}  // namespace gpsemu::ubx
