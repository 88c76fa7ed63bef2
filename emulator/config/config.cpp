#include "emulator/config/config.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "emulator/config/config_options.hpp"
#include "emulator/config/config_values.hpp"
#include "transport/pps.hpp"

namespace gpsemu {
namespace {

using namespace config_values;

/// Why a key cannot go in a [[receiver]] table (nullptr: it can).
const char* why_not_per_receiver(const std::string& name) {
  static const std::set<std::string> timeline{"rate", "latency", "start-time", "duration", "fast", "clock"};
  static const std::set<std::string> pps{"pps", "pps-width", "pps-polarity"};
  static const std::set<std::string> process{"realtime-priority", "lock-memory", "timer-slack", "log-level"};
  static const std::set<std::string> replay{"speed", "loop", "from", "to", "retime"};
  if (timeline.count(name)) {
    return "all receivers of a process share one epoch timeline (rate, latency, start-time, duration, fast, clock)";
  }
  if (pps.count(name)) return "a process drives at most one PPS line, for all its receivers";
  if (process.count(name)) return "it is a setting of the whole process";
  if (replay.count(name)) return "it applies to 'gpsemu replay' only";
  if (name == "receivers") return "the number of receivers is the number of [[receiver]] tables";
  if (name == "config" || name == "receiver") return "a [[receiver]] table holds option keys only";
  return nullptr;
}

const OptionDef* find_option(const std::string& name) {
  for (const auto& o : option_table()) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

/// A TOML value as the strings an option's apply() takes.
std::vector<std::string> toml_to_strings(const toml::node& node, const std::string& key) {
  std::vector<std::string> out;
  auto scalar = [&](const toml::node& n) -> std::string {
    if (auto s = n.value<std::string>(); s && n.is_string()) return *s;
    if (n.is_integer()) return std::to_string(*n.value<std::int64_t>());
    if (n.is_floating_point()) return fmt::format("{}", *n.value<double>());
    if (n.is_boolean()) return *n.value<bool>() ? "true" : "false";
    if (auto d = n.as_date_time()) {
      std::ostringstream s;
      s << *d;
      return s.str();
    }
    throw std::invalid_argument(fmt::format("{}: expected a string, number or boolean", key));
  };
  if (const auto* arr = node.as_array()) {
    for (const auto& item : *arr) out.push_back(scalar(item));
    if (out.empty()) throw std::invalid_argument(fmt::format("{}: empty list", key));
  } else {
    out.push_back(scalar(node));
  }
  return out;
}

/// The file's `[[receiver]]` tables: every key known and allowed per receiver, every value valid.
std::vector<ReceiverTable> parse_receiver_tables(const std::string& file, const toml::node& node) {
  const int line = static_cast<int>(node.source().begin.line);
  const auto* array = node.as_array();
  if (!array || !array->is_array_of_tables() || array->empty()) {
    throw ConfigError(fmt::format("config file {}:{}: 'receiver' must be [[receiver]] tables, one per receiver, "
                                  "each holding the option keys of that receiver", file, line));
  }
  std::vector<ReceiverTable> tables;
  for (const auto& item : *array) {
    const toml::table& t = *item.as_table();
    ReceiverTable table{file, static_cast<int>(t.source().begin.line), {}};
    Config scratch;  // each value is checked now, so a bad one is reported before anything opens
    for (const auto& [key, value] : t) {
      const std::string name{key.str()};
      const int key_line = static_cast<int>(value.source().begin.line);
      if (const char* why = why_not_per_receiver(name)) {
        throw ConfigError(fmt::format("config file {}:{}: key '{}' cannot be set in a [[receiver]] table: {}; "
                                      "set it at the top level", file, key_line, name, why));
      }
      const OptionDef* option = find_option(name);
      if (!option) {
        throw ConfigError(fmt::format("config file {}:{}: unknown key '{}' in a [[receiver]] table (keys are the "
                                      "long flag names, see gpsemu --help)", file, key_line, name));
      }
      try {
        std::vector<std::string> values = toml_to_strings(value, name);
        option->apply(scratch, values);
        table.keys.push_back({name, key_line, std::move(values)});
      } catch (const std::exception& e) {
        throw ConfigError(fmt::format("config file {}:{}: [[receiver]] key '{}': {}", file, key_line, name, e.what()));
      }
    }
    tables.push_back(std::move(table));
  }
  return tables;
}

void finish(Config& c) {
  if (c.clock.kind == ClockKind::fast) c.fast = true;
  if (c.fast && c.clock.kind != ClockKind::realtime && c.clock.kind != ClockKind::fast) {
    throw ConfigError(fmt::format("clock: --fast and --clock {} are two different clocks: give one", to_string(c.clock)));
  }
  if (c.fast) c.clock.kind = ClockKind::fast;
  if (c.pps && (c.clock.kind == ClockKind::scaled || c.clock.kind == ClockKind::lockstep)) {
    throw ConfigError(fmt::format("pps: a PPS pulse marks real seconds; it cannot be used with --clock {}",
                                  to_string(c.clock)));
  }
  if (c.pps && c.fast) {
    throw ConfigError("pps: a PPS pulse marks real seconds; it cannot be used with --fast");
  }
  if (c.pose_horizon_s > c.pose_timeout_s) {
    throw ConfigError(fmt::format("pose-horizon {} s is longer than pose-timeout {} s: a pose cannot be "
                                  "extrapolated past the time it goes stale", c.pose_horizon_s, c.pose_timeout_s));
  }
  // The cgrw one knob fills every axis not given explicitly.
  // The preset's ratios are per 1 Hz sample, so a different measurement rate needs every axis.
  if (c.cgrw_rate_hz && !(c.cgrw_east && c.cgrw_north && c.cgrw_up)) {
    throw ConfigError("cgrw-rate applies to parameters measured at that rate: give cgrw-east, cgrw-north "
                      "and cgrw-up too (gpsemu calibrate writes all four keys)");
  }
  const double window_s = c.noise.cgrw.window_s;
  c.noise.cgrw = noise::cgrw_preset(c.width_m);
  c.noise.cgrw.window_s = window_s;
  if (c.cgrw_rate_hz) c.noise.cgrw.rate_hz = *c.cgrw_rate_hz;
  if (c.cgrw_east) c.noise.cgrw.east = *c.cgrw_east;
  if (c.cgrw_north) c.noise.cgrw.north = *c.cgrw_north;
  if (c.cgrw_up) c.noise.cgrw.up = *c.cgrw_up;
  if (c.format.time_decimals < 3 && c.rate_hz > std::pow(10.0, c.format.time_decimals)) {
    throw ConfigError(fmt::format(
        "rate {} Hz needs more than {} time decimals: successive epochs would repeat a time "
        "(set time-decimals to {})", c.rate_hz, c.format.time_decimals, c.rate_hz > 100 ? 3 : 2));
  }
}

}  // namespace

const std::vector<OptionDef>& option_table() {
  static const std::vector<OptionDef> table = make_option_table();
  return table;
}

namespace {

/// Defaults, then the config file's keys (`file`, named `file_name` in messages) except those the
/// command line gives, then the command line's, then the derived settings.
Config build(const toml::table* file, const std::string& file_name, const RawOptions& command_line) {
  Config config;
  std::set<std::string> given_on_command_line;
  for (const auto& [name, values] : command_line) given_on_command_line.insert(name);

  if (file) {
    for (const auto& [key, node] : *file) {
      const std::string name{key.str()};
      const int line = static_cast<int>(node.source().begin.line);
      if (name == "receiver") {
        config.receiver_tables = parse_receiver_tables(file_name, node);
        continue;
      }
      const OptionDef* option = find_option(name);
      if (!option || name == "config") {
        throw ConfigError(fmt::format("config file {}:{}: unknown key '{}' (keys are the long flag names, "
                                      "see gpsemu --help)", file_name, line, name));
      }
      if (given_on_command_line.count(name)) continue;  // the command line wins
      try {
        option->apply(config, toml_to_strings(node, name));
      } catch (const std::exception& e) {
        throw ConfigError(fmt::format("config file {}:{}: key '{}': {}", file_name, line, name, e.what()));
      }
    }
  }
  for (const auto& [name, values] : command_line) {
    const OptionDef* option = find_option(name);
    if (!option) throw ConfigError(fmt::format("unknown option --{}", name));
    try {
      option->apply(config, values);
    } catch (const std::exception& e) {
      throw ConfigError(fmt::format("--{}: {}", name, e.what()));
    }
  }
  if (!config.receiver_tables.empty()) {
    const int tables = static_cast<int>(config.receiver_tables.size());
    if (tables > kMaxReceivers) {
      throw ConfigError(fmt::format("config file {}: {} [[receiver]] tables: at most {} receivers in one process",
                                    file_name, tables, kMaxReceivers));
    }
    if (config.receivers_given && config.receivers != tables) {
      throw ConfigError(fmt::format("receivers is {} but config file {} has {} [[receiver]] tables: the tables make "
                                    "the receivers, so give one table per receiver or leave receivers out",
                                    config.receivers, file_name, tables));
    }
    config.receivers = tables;
  }
  try {
    finish(config);
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError(e.what());
  }
  return config;
}

[[noreturn]] void throw_parse_error(const toml::parse_error& e, const std::string& file_name) {
  throw ConfigError(fmt::format("config file {}:{}: {}", file_name, e.source().begin.line, e.description()));
}

}  // namespace

Config build_config(const std::optional<std::string>& config_file, const RawOptions& command_line) {
  if (!config_file) return build(nullptr, {}, command_line);
  toml::table file;
  try {
    file = toml::parse_file(*config_file);
  } catch (const toml::parse_error& e) {
    throw_parse_error(e, *config_file);
  } catch (const std::exception& e) {
    throw ConfigError(fmt::format("config file {}: {}", *config_file, e.what()));
  }
  return build(&file, *config_file, command_line);
}

Config build_config_from_text(std::string_view toml_text, const std::string& source_name,
                              const RawOptions& command_line) {
  toml::table file;
  try {
    file = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    throw_parse_error(e, source_name);
  }
  return build(&file, source_name, command_line);
}

void apply_receiver_table(Config& config, const ReceiverTable& table) {
  for (const auto& key : table.keys) {
    const OptionDef* option = find_option(key.name);
    try {
      if (!option) throw std::invalid_argument("unknown key");
      option->apply(config, key.values);
    } catch (const std::exception& e) {
      throw ConfigError(fmt::format("config file {}:{}: [[receiver]] key '{}': {}", table.file, key.line, key.name,
                                    e.what()));
    }
  }
  try {
    finish(config);
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("config file {}:{}: [[receiver]]: {}", table.file, table.line, e.what()));
  } catch (const std::exception& e) {
    throw ConfigError(fmt::format("config file {}:{}: [[receiver]]: {}", table.file, table.line, e.what()));
  }
}

}  // namespace gpsemu
