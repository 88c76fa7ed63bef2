#include "emulator/protocol/ublox/state_file.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::protocol {

/// A state file is a few kilobytes; anything far larger is not one.
constexpr std::uintmax_t kMaxStateBytes = 1 << 20;

ubx::StoredLayers read_receiver_state(const std::string& path, ReceiverModel model) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return {};
  const auto size = std::filesystem::file_size(path, ec);
  if (ec || size > kMaxStateBytes) {
    throw std::invalid_argument(fmt::format("--receiver-state {}: {}", path,
                                            ec ? ec.message() : fmt::format("{} bytes is not a receiver state", size)));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(fmt::format("--receiver-state {}: cannot be read", path));
  std::ostringstream text;
  text << in.rdbuf();
  try {
    return ubx::stored_layers_from_text(text.str(), model);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("--receiver-state {}: {}", path, e.what()));
  }
}

bool write_receiver_state(const StateFile& file, const ubx::StoredLayers& layers, ReceiverModel model,
                          std::string& error) {
  if (!file.replace) {
    error = file.path + ": no way to write it was given";
    return false;
  }
  return file.replace(file.path, ubx::to_text(layers, model), error);
}

}  // namespace gpsemu::protocol
