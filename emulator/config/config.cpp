// Loading a configuration: defaults, the TOML file, the command line, the [[receiver]] tables;
// then resolving it into a Config (validate.hpp, fleet_config.hpp).
#include "emulator/config/config.hpp"
#include "emulator/config/toml_shape.hpp"

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "emulator/config/config_options.hpp"
#include "emulator/config/config_values.hpp"
#include "emulator/config/fleet_config.hpp"
#include "emulator/config/profiles.hpp"
#include "emulator/config/validate.hpp"

namespace gpsemu {
namespace {

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

/// Whether `option` takes text (an output spec, a file, a name): a TOML number or boolean for it is
/// a mistake, refused even when the command line gives the option too (`output = 5` is never
/// silently replaced by --output).
bool takes_text(const OptionDef& option) {
  static const std::set<std::string, std::less<>> text{"SPEC", "FILE", "CLOCK", "KIND", "LEVEL", "MODEL"};
  return text.contains(option.value_name);
}

/// Refuses a number, boolean or date for a text option (in a list too).
void check_text_type(const OptionDef& option, const toml::node& node) {
  if (!takes_text(option)) return;
  const auto check = [&](const toml::node& n) {
    if (n.is_string()) return;
    const char* type = n.is_integer() ? "an integer" : n.is_floating_point() ? "a number" : n.is_boolean() ? "a boolean"
                                                                                                          : "not a string";
    throw std::invalid_argument(fmt::format("expected a string ({}), got {}{}", option.value_name, type,
                                            n.is_table() ? "" : fmt::format(" ({})", toml_to_strings(n, option.name).front())));
  };
  if (const auto* arr = node.as_array()) {
    for (const auto& item : *arr) check(item);
  } else {
    check(node);
  }
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
    ConfigDraft scratch;  // each value is checked now, so a bad one is reported before anything opens
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
        check_text_type(*option, value);
        std::vector<std::string> values = toml_to_strings(value, name);
        option->apply(scratch, values);
        table.keys.push_back({name, key_line, std::move(values)});
      } catch (const std::exception& e) {
        throw ConfigError(config_values::shorten_quoted(
            fmt::format("config file {}:{}: [[receiver]] key '{}': {}", file, key_line, name, e.what())));
      }
    }
    tables.push_back(std::move(table));
  }
  return tables;
}

}  // namespace

const std::vector<OptionDef>& option_table() {
  static const std::vector<OptionDef> table = make_option_table();
  return table;
}

const OptionDef* find_option(std::string_view name) {
  for (const auto& o : option_table()) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

namespace {

/// The loaded configuration from the options' values: derived values resolved, every check made,
/// one ReceiverSettings per receiver.
Config resolve(ConfigDraft& draft) {
  Config config;
  try {
    resolve_timeline(draft);
    (void)resolve_receiver(draft.receiver, draft.timeline);  // the shared settings, before any table's
    config.receivers = resolve_receivers(draft);
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError(config_values::shorten_quoted(e.what()));
  }
  check_fault_receivers(draft.timeline.faults, config.receivers.size());
  check_fault_times(draft.timeline.faults, draft.timeline);
  check_fault_overlaps(draft.timeline.faults, draft.timeline);
  config.process = std::move(draft.process);
  config.timeline = std::move(draft.timeline);
  config.replay = std::move(draft.replay);
  return config;
}

/// The receiver profile named on the command line (--profile) or else in the file (`profile = "NAME"`),
/// or nullptr. Throws ConfigError for an unknown name.
const profiles::Profile* named_profile(const toml::table* file, const std::string& file_name,
                                       const RawOptions& command_line) {
  try {
    for (const auto& [name, values] : command_line) {
      if (name == "profile") return &profiles::get(values.back());
    }
  } catch (const std::exception& e) {
    throw ConfigError(fmt::format("--profile: {}", e.what()));
  }
  const toml::node* node = file ? file->get("profile") : nullptr;
  if (!node || !node->is_string()) return nullptr;  // a [profile] table describes the file itself
  try {
    return &profiles::get(*node->value<std::string>());
  } catch (const std::exception& e) {
    throw ConfigError(fmt::format("config file {}:{}: key 'profile': {}", file_name, node->source().begin.line, e.what()));
  }
}

/// A profile's keys onto `config` (before the file's and the command line's, which override them).
void apply_profile(ConfigDraft& config, const profiles::Profile& profile) {
  const std::string where = fmt::format("profile {}", profile.name);
  toml::table keys;
  try {
    keys = toml::parse(profile.text, where);
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format("{}:{}: {}", where, e.source().begin.line, e.description()));
  }
  for (const auto& [key, node] : keys) {
    const std::string name{key.str()};
    if (name == "profile") continue;  // what `gpsemu profiles` lists
    const OptionDef* option = find_option(name);
    try {
      if (!option || (option->scope != OptionScope::receiver && option->scope != OptionScope::timeline)) {
        throw std::invalid_argument("not a receiver or timeline option");
      }
      option->apply(config, toml_to_strings(node, name));
    } catch (const std::exception& e) {
      throw ConfigError(fmt::format("{}:{}: key '{}': {}", where, node.source().begin.line, name, e.what()));
    }
  }
}

/// Defaults, then the receiver profile's keys (--profile or the file's `profile`), then the config
/// file's keys (`file`, named `file_name` in messages) except those the command line gives, then the
/// command line's, then the derived settings.
Config build(const toml::table* file, const std::string& file_name, const RawOptions& command_line) {
  ConfigDraft config;
  std::set<std::string> given_on_command_line;
  for (const auto& [name, values] : command_line) given_on_command_line.insert(name);
  if (const profiles::Profile* profile = named_profile(file, file_name, command_line)) {
    apply_profile(config, *profile);
    config.process.profile = std::string(profile->name);
  }

  if (file) {
    for (const auto& [key, node] : *file) {
      const std::string name{key.str()};
      const int line = static_cast<int>(node.source().begin.line);
      if (name == "receiver" && !node.is_string()) {  // a string is --receiver's value
        config.receiver_tables = parse_receiver_tables(file_name, node);
        continue;
      }
      if (name == "profile" && node.is_table()) continue;  // a profile's own description (profiles.hpp)
      if (name == "fault") {  // [[fault]] tables: the scenario (docs/faults.md)
        for (faults::Fault& f : parse_fault_tables("config file " + file_name, node)) config.timeline.faults.push_back(std::move(f));
        continue;
      }
      const OptionDef* option = find_option(name);
      if (!option || name == "config") {
        throw ConfigError(fmt::format("config file {}:{}: unknown key '{}' (keys are the long flag names, "
                                      "see gpsemu --help)", file_name, line, name));
      }
      try {
        check_text_type(*option, node);
        if (given_on_command_line.count(name)) continue;  // the command line wins
        option->apply(config, toml_to_strings(node, name));
      } catch (const std::exception& e) {
        throw ConfigError(config_values::shorten_quoted(
            fmt::format("config file {}:{}: key '{}': {}", file_name, line, name, e.what())));
      }
    }
  }
  for (const auto& [name, values] : command_line) {
    const OptionDef* option = find_option(name);
    if (!option) throw ConfigError(fmt::format("unknown option --{}", name));
    try {
      option->apply(config, values);
    } catch (const std::exception& e) {
      throw ConfigError(config_values::shorten_quoted(fmt::format("--{}: {}", name, e.what())));
    }
  }
  check_fleet_size(config, file_name);
  return resolve(config);
}

/// What a config file is not: a regular file (a device or FIFO would read as empty or block).
const char* kind_of(std::filesystem::file_type type) {
  using T = std::filesystem::file_type;
  switch (type) {
    case T::directory: return "a directory";
    case T::fifo: return "a FIFO";
    case T::character:
    case T::block: return "a device";
    case T::socket: return "a socket";
    default: return "not a regular file";
  }
}

}  // namespace

/// The whole text of a config file. Refused unless it is a regular file (through a link): its
/// type is asked first, so a FIFO is never opened (an open would wait for a writer).
std::string read_config_file(const std::string& path, std::string_view what) {
  const auto fail = [&](int error) {
    return ConfigError(fmt::format("{} {}: {}", what, path, std::generic_category().message(error)));
  };
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (status.type() == std::filesystem::file_type::not_found) throw fail(ENOENT);
  if (ec) throw fail(ec.value());
  if (!std::filesystem::is_regular_file(status)) {
    throw ConfigError(fmt::format("{} {}: {}; give a regular TOML file", what, path, kind_of(status.type())));
  }
  const auto too_large = [&path, what](std::uint64_t bytes) {
    return ConfigError(fmt::format("{} {}: larger than 1 MiB ({} bytes); a {} may have at most {} "
                                   "bytes", what, path, bytes, what, kMaxConfigFileBytes));
  };
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw fail(ec.value());
  if (size > kMaxConfigFileBytes) throw too_large(size);
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fail(errno != 0 ? errno : EACCES);
  std::string text;
  char buffer[65536];
  while (in) {
    in.read(buffer, sizeof buffer);
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxConfigFileBytes) throw too_large(text.size());  // it grew while being read
  }
  if (in.bad()) throw fail(errno != 0 ? errno : EIO);
  return text;
}

namespace {

[[noreturn]] void throw_parse_error(const toml::parse_error& e, const std::string& file_name) {
  throw ConfigError(config_values::shorten_quoted(
      fmt::format("config file {}:{}: {}", file_name, e.source().begin.line, e.description())));
}

}  // namespace

Config build_config(const std::optional<std::string>& config_file, const RawOptions& command_line) {
  if (!config_file) return build(nullptr, {}, command_line);
  const std::string text = read_config_file(*config_file, "config file");
  check_toml_shape(text, "config file", *config_file);
  toml::table file;
  try {
    file = toml::parse(text, *config_file);
  } catch (const toml::parse_error& e) {
    throw_parse_error(e, *config_file);
  } catch (const std::exception& e) {
    throw ConfigError(fmt::format("config file {}: {}", *config_file, e.what()));
  }
  return build(&file, *config_file, command_line);
}

Config build_config_from_text(std::string_view toml_text, const std::string& source_name,
                              const RawOptions& command_line) {
  if (toml_text.size() > kMaxConfigFileBytes) {
    throw ConfigError(fmt::format("config file {}: larger than 1 MiB ({} bytes); a config file may have at most {} "
                                  "bytes", source_name, toml_text.size(), kMaxConfigFileBytes));
  }
  check_toml_shape(toml_text, "config file", source_name);
  toml::table file;
  try {
    file = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    throw_parse_error(e, source_name);
  }
  return build(&file, source_name, command_line);
}

}  // namespace gpsemu
