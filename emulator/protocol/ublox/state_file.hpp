// --receiver-state FILE: a u-blox's stored configuration layers (BBR and flash,
// ubx/config_layers.hpp) kept across runs. Read once at start (a missing file is a receiver with
// nothing stored); written again, whole, each time a client changes a stored layer (CFG-VALSET to
// BBR or flash, CFG-VALDEL, CFG-CFG save or clear), through a temporary file renamed over it, so a
// run stopped at any moment leaves the old or the new state, never half of one.
#pragma once

#include <functional>
#include <string>
#include <string_view>

#include "emulator/ubx/config_layers.hpp"

namespace gpsemu::protocol {

/// Replaces the file at `path` with `text` whole, so a reader sees the old or the new text, never
/// half of one; false with `error` set when it cannot. The OS layer's (transport/posix/fd.hpp:
/// posix::replace_file), handed in by whoever builds the protocol: the protocol makes no OS call.
using ReplaceFile = std::function<bool(const std::string& path, std::string_view text, std::string& error)>;

/// Where a u-blox's stored layers are kept (--receiver-state) and how the file is written.
struct StateFile {
  std::string path;
  ReplaceFile replace;
};

/// The layers `path` holds for `model`; empty layers when the file does not exist. Throws
/// std::invalid_argument naming the file and line when it cannot be read or is not a state of
/// `model`.
[[nodiscard]] ubx::StoredLayers read_receiver_state(const std::string& path, ReceiverModel model);

/// Writes `layers` to `file`; false with `error` set when it cannot.
[[nodiscard]] bool write_receiver_state(const StateFile& file, const ubx::StoredLayers& layers, ReceiverModel model,
                                        std::string& error);

}  // namespace gpsemu::protocol
