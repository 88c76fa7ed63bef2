// The option table: every flag of the command line and key of the config file, its help text,
// its scope, and how its value sets the ConfigDraft (config.cpp builds a Config with it): the
// options write raw values here, which are resolved once every option is in. Internal to config/.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "emulator/config/config.hpp"

namespace gpsemu {

/// The most receivers one process runs.
inline constexpr int kMaxReceivers = 1024;

/// One `[[receiver]]` table of the config file: option keys that override the shared settings for
/// one receiver of a fleet (see fleet_config.hpp). Values are kept as text and applied per receiver.
struct ReceiverTable {
  struct Key {
    std::string name;                 ///< option name (the long flag without dashes)
    int line = 0;                     ///< line in the config file
    std::vector<std::string> values;  ///< as an option's apply() takes them
  };
  std::string file;  ///< the config file
  int line = 0;      ///< line of the table's `[[receiver]]` header
  std::vector<Key> keys;
};

/// One receiver's options as given: the settings, plus what is resolved at the end (the specs as
/// text, since they may hold fleet templates; the cgrw one knob and explicit axes).
struct ReceiverDraft {
  ReceiverSettings settings;                 ///< source, outputs and noise.cgrw axes filled when resolved
  std::string source = "sim:stationary";     ///< --source, may hold {i} / {B+i}
  std::vector<std::string> outputs{"pty:/tmp/gpsemu"};  ///< --output, each may hold templates
  std::optional<std::string> tee;            ///< --tee, may hold templates
  std::optional<std::string> rtcm;           ///< --rtcm, may hold templates (a port per receiver)
  double width_m = 1.0;                      ///< cgrw one knob: horizontal width (metres)
  std::optional<noise::CgrwAxis> cgrw_east, cgrw_north, cgrw_up;  ///< explicit cgrw axes (else from width_m)
  std::optional<double> cgrw_rate_hz;        ///< rate the explicit axes were measured at (Hz)
  /// The composite's own cgrw smooth axes (composite-cgrw-*): all three or none.
  std::array<std::optional<noise::CgrwAxis>, 3> composite_cgrw;
  /// --velocity-noise, --velocity-wander as given (else the defaults; 0 with --noise none).
  std::optional<double> velocity_white_mps, velocity_wander_mps;
};

/// Every option's raw value while a configuration loads.
struct ConfigDraft {
  ProcessSettings process;
  TimelineSettings timeline;
  ReplaySettings replay;
  ReceiverDraft receiver;                     ///< the shared settings of every receiver
  bool fast = false;                          ///< --fast given (resolved into timeline.clock)
  int receivers = 1;                          ///< --receivers, 1..kMaxReceivers
  bool receivers_given = false;               ///< --receivers (or the file's `receivers`) was given
  std::vector<ReceiverTable> receiver_tables; ///< the file's [[receiver]] tables; when any, one receiver each
};

/// The whole text of a regular file of at most kMaxConfigFileBytes; `what` ("config file",
/// "scenario file") names it in messages. Throws ConfigError.
[[nodiscard]] std::string read_config_file(const std::string& path, std::string_view what);

/// The `fault` key of a TOML file: [[fault]] tables (scenario.cpp), `file` ("config file run.toml")
/// in their origin. Throws ConfigError naming the file, the line of the key at fault and the key.
[[nodiscard]] std::vector<faults::Fault> parse_fault_tables(const std::string& file, const toml::node& node);
/// A scenario file (--scenario): [[fault]] tables and nothing else. Throws ConfigError.
[[nodiscard]] std::vector<faults::Fault> load_scenario(const std::string& path);
/// Every fault's receiver index exists among `receivers`. Throws ConfigError.
void check_fault_receivers(const std::vector<faults::Fault>& faults, std::size_t receivers);
/// Every fault starts before the end of the run (--duration; an `at_utc` when --start-time is
/// known): one that never would is refused. Throws ConfigError naming its file, line and key.
void check_fault_times(const std::vector<faults::Fault>& faults, const TimelineSettings& timeline);
/// No two spoofs act on one receiver at once (their drags would add up unnoticed). Throws
/// ConfigError naming the second one's file and line and the first one.
void check_fault_overlaps(const std::vector<faults::Fault>& faults, const TimelineSettings& timeline);

/// Appends the composite noise model's options (--composite-*; composite_options.cpp) to `table`.
void add_composite_options(std::vector<OptionDef>& table);
/// Appends the RTK options (--rtcm, --rtk-*; rtk_options.cpp) to `table`.
void add_rtk_options(std::vector<OptionDef>& table);

/// Every option, in --help order.
[[nodiscard]] std::vector<OptionDef> make_option_table();

}  // namespace gpsemu
