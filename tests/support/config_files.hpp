// Config tests' helpers: a config file written to the temporary directory, and the ConfigError
// message of building a configuration (or "(no error)").
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "emulator/config/config.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu::test {

/// Writes `text` to a file named `prefix` + `name` in this test process's scratch directory.
inline std::string write_temp(const std::string& prefix, const std::string& name, const std::string& text) {
  const auto path = scratch_root() / (prefix + name);
  std::ofstream(path) << text;
  return path.string();
}

/// The ConfigError message of building the configuration (fleet expanded too), or "(no error)".
inline std::string config_error_of(const std::optional<std::string>& file, const RawOptions& cli) {
  try {
    (void)build_config(file, cli);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace gpsemu::test
