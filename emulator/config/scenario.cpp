// Scenario files: [[fault]] tables (--scenario FILE, or inside --config) into faults::Fault values;
// or a --tee file, whose "# fault" lines are the live events of a session (faults/tee_events.hpp).
#include <fmt/format.h>

#include "emulator/faults/tee_events.hpp"

#include "emulator/config/config_options.hpp"
#include "emulator/config/config_values.hpp"

namespace gpsemu {

std::vector<faults::Fault> parse_fault_tables(const std::string& file, const toml::node& node) {
  const int line = static_cast<int>(node.source().begin.line);
  const auto* array = node.as_array();
  if (!array || !array->is_array_of_tables()) {
    throw ConfigError(fmt::format("{}:{}: 'fault' must be [[fault]] tables, each with kind, at, duration and the "
                                  "fault's parameters (docs/faults.md)", file, line));
  }
  std::vector<faults::Fault> out;
  for (const auto& item : *array) {
    const toml::table& t = *item.as_table();
    const int table_line = static_cast<int>(t.source().begin.line);
    faults::FaultKeys keys;
    for (const auto& [key, value] : t) {
      const std::string name{key.str()};
      const int key_line = static_cast<int>(value.source().begin.line);
      if (value.is_string()) {
        keys.emplace_back(name, *value.value<std::string>());
      } else if (value.is_integer() || value.is_floating_point()) {
        keys.emplace_back(name, *value.value<double>());
      } else if (value.is_boolean()) {
        keys.emplace_back(name, std::string(*value.value<bool>() ? "true" : "false"));
      } else {
        throw ConfigError(fmt::format("{}:{}: [[fault]] key '{}': expected a number, a string or true/false", file,
                                      key_line, name));
      }
    }
    try {
      out.push_back(faults::make_fault(keys));
    } catch (const std::exception& e) {
      throw ConfigError(config_values::shorten_quoted(fmt::format("{}:{}: [[fault]]: {}", file, table_line, e.what())));
    }
  }
  return out;
}

std::vector<faults::Fault> load_scenario(const std::string& path) {
  const std::string text = read_config_file(path, "scenario file");
  if (faults::looks_like_tee(text)) {
    try {
      return faults::faults_from_tee(text);
    } catch (const std::exception& e) {
      throw ConfigError(config_values::shorten_quoted(fmt::format("scenario file {} (a --tee file): {}", path, e.what())));
    }
  }
  toml::table file;
  try {
    file = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw ConfigError(config_values::shorten_quoted(
        fmt::format("scenario file {}:{}: {}", path, e.source().begin.line, e.description())));
  }
  std::vector<faults::Fault> out;
  for (const auto& [key, node] : file) {
    if (key.str() != "fault") {
      throw ConfigError(fmt::format("scenario file {}:{}: unknown key '{}' (a scenario holds [[fault]] tables only)", path,
                                    node.source().begin.line, key.str()));
    }
    out = parse_fault_tables(path, node);
  }
  return out;
}

void check_fault_receivers(const std::vector<faults::Fault>& faults, std::size_t receivers) {
  for (const faults::Fault& f : faults) {
    if (f.receiver && static_cast<std::size_t>(*f.receiver) >= receivers) {
      throw ConfigError(fmt::format("fault {}: there is no receiver {} (receivers are 0..{})", f.describe(), *f.receiver,
                                    receivers - 1));
    }
  }
}

}  // namespace gpsemu
