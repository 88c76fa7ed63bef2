// --receiver-state FILE: a u-blox's stored configuration layers (BBR and flash,
// ubx/config_layers.hpp) kept across runs. Read once at start (a missing file is a receiver with
// nothing stored); written again, whole, each time a client changes a stored layer (CFG-VALSET to
// BBR or flash, CFG-VALDEL, CFG-CFG save or clear), through a temporary file renamed over it, so a
// run stopped at any moment leaves the old or the new state, never half of one.
#pragma once

#include <string>

#include "emulator/ubx/config_layers.hpp"

namespace gpsemu::protocol {

/// The layers `path` holds for `model`; empty layers when the file does not exist. Throws
/// std::invalid_argument naming the file and line when it cannot be read or is not a state of
/// `model`.
[[nodiscard]] ubx::StoredLayers read_receiver_state(const std::string& path, ReceiverModel model);

/// Writes `layers` to `path`; false with `error` set when it cannot.
[[nodiscard]] bool write_receiver_state(const std::string& path, const ubx::StoredLayers& layers,
                                        ReceiverModel model, std::string& error);

}  // namespace gpsemu::protocol
