// Everything a run is configured by (settings.hpp, grouped by scope), and the one table of options
// shared by the command line (CLI11) and the TOML config file (--config): the same keys, validated
// by the same code; command-line flags override the file. Where an option applies (process,
// timeline, receiver, replay) is stated once, in its OptionDef.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emulator/config/settings.hpp"

namespace gpsemu {

/// A loaded configuration: every spec parsed, every derived value resolved, one ReceiverSettings
/// per receiver (--receivers N with its templates expanded, or one per [[receiver]] table).
struct Config {
  ProcessSettings process;
  TimelineSettings timeline;
  std::vector<ReceiverSettings> receivers = std::vector<ReceiverSettings>(1);  ///< at least one, in index order
  ReplaySettings replay;

  /// The first receiver: the only one of a run without --receivers or tables (the subcommands').
  [[nodiscard]] const ReceiverSettings& receiver() const { return receivers.front(); }
  [[nodiscard]] ReceiverSettings& receiver() { return receivers.front(); }
};

/// Where an option applies: which settings it sets, and so whether a [[receiver]] table may set it.
enum class OptionScope {
  process,   ///< ProcessSettings: the whole process
  fleet,     ///< the number of receivers (--receivers)
  timeline,  ///< TimelineSettings: the epoch timeline all receivers share
  pps,       ///< TimelineSettings: the one PPS line of the process
  receiver,  ///< ReceiverSettings: may differ between receivers
  replay,    ///< ReplaySettings: `gpsemu replay` only
};

/// The options as they are being applied, before the derived values are resolved (config_options.hpp).
struct ConfigDraft;

/// One option, usable as `--name VALUE` and as `name = VALUE` in the config file.
struct OptionDef {
  std::string name;        ///< long flag without dashes, and the config key
  std::string value_name;  ///< "HZ", "S", "LAT,LON,ALT"; empty for a flag
  std::string help;        ///< with unit and default
  OptionScope scope = OptionScope::receiver;
  bool repeatable = false; ///< may be given several times (an array in the config file)
  std::function<void(ConfigDraft&, const std::vector<std::string>&)> apply;  ///< throws std::invalid_argument
};

/// The table of every option of the emulator.
[[nodiscard]] const std::vector<OptionDef>& option_table();
/// The option named `name` (the long flag without dashes), or nullptr.
[[nodiscard]] const OptionDef* find_option(std::string_view name);

/// Thrown for a bad flag, value or config file: the message names the key (and file and line).
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Raw values gathered from the command line: option name -> values, in the order given.
using RawOptions = std::vector<std::pair<std::string, std::vector<std::string>>>;

/// Largest config file read (bytes): a real one is a few KiB.
inline constexpr std::uint64_t kMaxConfigFileBytes = 1024 * 1024;

/// Builds the configuration: defaults, then the config file's keys (if `config_file`), then the
/// command line's, then each [[receiver]] table's; then resolves and checks it (validate.hpp):
/// the cgrw preset from width, the specs parsed, the fleet expanded. Throws ConfigError.
[[nodiscard]] Config build_config(const std::optional<std::string>& config_file,
                                  const RawOptions& command_line);

/// The same with the config file's text given directly (no file is read, e.g. for fuzzing);
/// `source_name` stands for the file's path in messages, which are otherwise build_config's.
[[nodiscard]] Config build_config_from_text(std::string_view toml_text, const std::string& source_name,
                                            const RawOptions& command_line);

/// What the run knows of its epochs once it starts (the Runner; --start-time: at start-up too).
struct RunTimes {
  UtcNs first_epoch;
  bool first_epoch_is_now = false;     ///< no --start-time: the run's own first epoch (messages say so)
  std::optional<double> run_s;         ///< --duration (none: until stopped)
  std::optional<double> last_epoch_s;  ///< the last epoch after the first, when no receiver leaves the run's grid
};
/// Every fault starts in the run: an `at_utc` before its end and not over before it begins, and
/// none after the last epoch (when that is known). Throws ConfigError naming its file, line and key.
void check_fault_run_times(const std::vector<faults::Fault>& faults, const RunTimes& run);

}  // namespace gpsemu
