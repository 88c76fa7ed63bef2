// Scenario files: [[fault]] tables (--scenario FILE, or inside --config) into faults::Fault values;
// or a --tee file, whose "# fault" lines are the live events of a session (faults/tee_events.hpp).
#include <algorithm>
#include <chrono>
#include <limits>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "emulator/config/toml_shape.hpp"
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
    faults::FaultOrigin origin{file, static_cast<int>(t.source().begin.line), {}};
    faults::FaultKeys keys;
    for (const auto& [key, value] : t) {
      const std::string name{key.str()};
      const int key_line = static_cast<int>(value.source().begin.line);
      origin.key_lines.emplace_back(name, key_line);
      if (value.is_string()) {
        keys.emplace_back(name, *value.value<std::string>());
      } else if (value.is_integer()) {  // value<double>() is empty for an integer a double cannot hold exactly
        keys.emplace_back(name, static_cast<double>(*value.value<std::int64_t>()));
      } else if (value.is_floating_point()) {
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
      // make_fault's message starts with the key it is about ("db: ..."): that key's line.
      const std::string message = e.what();
      const std::size_t colon = message.find(": ");
      throw ConfigError(config_values::shorten_quoted(
          origin.prefix(colon == std::string::npos ? std::string() : message.substr(0, colon)) + message));
    }
    out.back().origin = std::move(origin);
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
  check_toml_shape(text, "scenario file", path);
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
    out = parse_fault_tables("scenario file " + path, node);
  }
  return out;
}

void check_fault_receivers(const std::vector<faults::Fault>& faults, std::size_t receivers) {
  for (const faults::Fault& f : faults) {
    if (f.receiver && static_cast<std::size_t>(*f.receiver) >= receivers) {
      const std::string where = f.origin.file.empty() ? fmt::format("fault {}: ", f.describe()) : f.origin.prefix("receiver");
      throw ConfigError(fmt::format("{}receiver: there is no receiver {} (receivers are 0..{}: --receivers N)", where,
                                    *f.receiver, receivers - 1));
    }
  }
}

namespace {

/// [start, end) of `f` in seconds after the first epoch (end: infinity without a duration, or for
/// an area's fault, which may start again on each visit); nothing when it cannot be told (at_utc
/// without --start-time).
std::optional<std::pair<double, double>> fault_window_s(const faults::Fault& f, const TimelineSettings& timeline) {
  double start_s = f.at_s;
  if (f.at_utc) {
    if (!timeline.start_time) return std::nullopt;
    start_s = std::chrono::duration<double>(*f.at_utc - *timeline.start_time).count();
  }
  const double end_s = f.duration_s && !f.where ? start_s + *f.duration_s + f.ramp_out_s : std::numeric_limits<double>::infinity();
  return std::pair{start_s, end_s};
}

std::string named(const faults::Fault& f) {
  return f.origin.file.empty() ? fmt::format("the fault {}", f.describe())
                               : fmt::format("the spoof at {}:{}", f.origin.file, f.origin.table_line);
}

}  // namespace

void check_fault_overlaps(const std::vector<faults::Fault>& faults, const TimelineSettings& timeline) {
  for (std::size_t i = 0; i < faults.size(); ++i) {
    const faults::Fault& a = faults[i];
    if (!a.is<faults::Spoof>()) continue;
    for (std::size_t j = i + 1; j < faults.size(); ++j) {
      const faults::Fault& b = faults[j];
      if (!b.is<faults::Spoof>()) continue;
      if (a.receiver && b.receiver && *a.receiver != *b.receiver) continue;
      const auto wa = fault_window_s(a, timeline), wb = fault_window_s(b, timeline);
      if (!wa || !wb || wb->first >= wa->second || wa->first >= wb->second) continue;
      const std::string where = b.origin.file.empty() ? fmt::format("fault {}: ", b.describe()) : b.origin.prefix("kind");
      throw ConfigError(fmt::format("{}spoof: overlaps {} on the same receiver from {:g} s: two spoofers would add their "
                                    "drags; give one spoof, or let the second start after the first ends (its ramp_out_s "
                                    "included)", where, named(a), std::max(wa->first, wb->first)));
    }
  }
}

void check_fault_times(const std::vector<faults::Fault>& faults, const TimelineSettings& timeline) {
  if (timeline.duration_s) {
    const double run_s = *timeline.duration_s;
    for (const faults::Fault& f : faults) {
      if (f.at_utc || f.at_s < run_s) continue;
      const std::string where = f.origin.file.empty() ? fmt::format("fault {}: ", f.describe()) : f.origin.prefix("at");
      throw ConfigError(fmt::format("{}at: {:g} s is not before the end of the run (--duration {:g} s): the fault would "
                                    "never start", where, f.at_s, run_s));
    }
  }
  // Without --start-time the first epoch is known when the run starts (Runner): checked there.
  if (timeline.start_time) check_fault_run_times(faults, {*timeline.start_time, false, timeline.duration_s, std::nullopt});
}

void check_fault_run_times(const std::vector<faults::Fault>& faults, const RunTimes& run) {
  const std::string first = run.first_epoch_is_now ? fmt::format("its first epoch, now: {}", format_iso8601_utc(run.first_epoch))
                                                   : format_iso8601_utc(run.first_epoch);
  const std::string advice = run.first_epoch_is_now ? "; --start-time T runs it at another time" : "";
  const auto seconds = [](double s) { return std::chrono::duration_cast<UtcNs::duration>(std::chrono::duration<double>(s)); };
  for (const faults::Fault& f : faults) {
    const std::string key = f.at_utc ? "at_utc" : "at";
    const std::string where = f.origin.file.empty() ? fmt::format("fault {}: ", f.describe()) : f.origin.prefix(key);
    if (f.at_utc && run.run_s && *f.at_utc >= run.first_epoch + seconds(*run.run_s)) {
      throw ConfigError(where + fmt::format("at_utc: {} is not before the end of the run ({} + --duration {:g} s): the "
                                            "fault would never start{}", format_iso8601_utc(*f.at_utc), first, *run.run_s,
                                            advice));
    }
    // An area's fault is armed from at_utc (its duration is a visit's): never over before the run.
    if (f.at_utc && f.duration_s && !f.where && *f.at_utc + seconds(*f.duration_s + f.ramp_out_s) <= run.first_epoch) {
      throw ConfigError(where + fmt::format("at_utc: {} + {:g} s is over before the run begins ({}): the fault would "
                                            "never be on{}", format_iso8601_utc(*f.at_utc), *f.duration_s + f.ramp_out_s,
                                            first, advice));
    }
    // Between the last epoch and the end of --duration: no epoch comes at or after it.
    const double start_s = f.at_utc ? std::chrono::duration<double>(*f.at_utc - run.first_epoch).count() : f.at_s;
    const auto ns = [](double s) { return std::llround(s * 1e9); };
    if (run.last_epoch_s && run.run_s && ns(start_s) > ns(*run.last_epoch_s)) {
      const std::string what = f.at_utc ? fmt::format("{} ({:g} s after the first epoch)", format_iso8601_utc(*f.at_utc), start_s)
                                        : fmt::format("{:g} s", start_s);
      throw ConfigError(where + fmt::format("{}: {} is after the run's last epoch (at {:g} s of --duration {:g} s): the "
                                            "fault would never start", key, what, *run.last_epoch_s, *run.run_s));
    }
  }
}

}  // namespace gpsemu
