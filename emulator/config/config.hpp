// Everything a run is configured by, with units and defaults, and the one table of options shared
// by the command line (CLI11) and the TOML config file (--config): the same keys, validated by the
// same code; command-line flags override the file.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/pipeline/clock.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "transport/posix/realtime.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/replay/replay_options.hpp"
#include "emulator/sources/sim.hpp"
#include "emulator/model/time.hpp"
#include "nmea/fix.hpp"

namespace gpsemu {

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

struct Config {
  // Pose source
  std::string source = "sim:stationary";        ///< sim:NAME, udp:[HOST:]PORT, tcp:[HOST:]PORT
  Geodetic origin{43.0725, -89.4125, 260.0};    ///< local frame origin; alt above MSL (metres)
  sources::SimOptions sim;
  double pose_timeout_s = 1.0;                   ///< udp:/tcp: a pose older than this is no fix (seconds)
  double pose_horizon_s = 0.2;                   ///< udp:/tcp: longest extrapolation past the newest pose (seconds)
  // Clock
  double rate_hz = 1.0;                          ///< epochs per second
  double latency_s = 0.05;                       ///< epoch time to first byte (seconds)
  std::optional<UtcNs> start_time;               ///< first epoch; default: the next epoch after now
  std::optional<double> duration_s;              ///< stop after this much epoch time; default: run until stopped
  bool fast = false;                             ///< no pacing: generate as fast as possible
  ClockSpec clock;                               ///< realtime | scaled:K | fast | lockstep (clock.hpp)
  replay::ReplayOptions replay;                  ///< gpsemu replay: speed, loop, from/to, retime
  std::optional<std::string> tee;                ///< copy of everything sent, with send times (default none)
  // Noise
  noise::NoiseConfig noise;
  double width_m = 1.0;                          ///< cgrw one-knob horizontal width (metres)
  std::optional<noise::CgrwAxis> cgrw_east, cgrw_north, cgrw_up;  ///< explicit cgrw axes (else from width_m)
  std::optional<double> cgrw_rate_hz;            ///< rate the explicit axes were measured at (Hz)
  std::uint64_t seed = 1;
  // Receiver and sentences
  ReceiverOptions receiver;
  nmea::FormatOptions format;
  // Outputs
  std::vector<std::string> outputs{"pty:/tmp/gpsemu"};
  // PPS
  std::optional<std::string> pps;                ///< gpio:CHIP:LINE | modem:RTS | modem:DTR; default none
  double pps_width_s = 0.1;                      ///< pulse width (seconds)
  bool pps_active_low = false;                   ///< line low (GPIO 0, modem line cleared) during the pulse
  std::string log_level = "info";
  // Many receivers in one process (fleet_config.hpp)
  int receivers = 1;                             ///< receivers built from these settings, 1..1024
  bool receivers_given = false;                  ///< --receivers (or the file's `receivers`) was given
  std::vector<ReceiverTable> receiver_tables;    ///< the file's [[receiver]] tables; when any, one receiver each
  posix::RealtimeSettings realtime;              ///< SCHED_FIFO priority, mlockall, timer slack (realtime.hpp)
};

/// One option, usable as `--name VALUE` and as `name = VALUE` in the config file.
struct OptionDef {
  std::string name;        ///< long flag without dashes, and the config key
  std::string value_name;  ///< "HZ", "S", "LAT,LON,ALT"; empty for a flag
  std::string help;        ///< with unit and default
  bool repeatable = false; ///< may be given several times (an array in the config file)
  std::function<void(Config&, const std::vector<std::string>&)> apply;  ///< throws std::invalid_argument
};

/// The table of every option of the emulator.
[[nodiscard]] const std::vector<OptionDef>& option_table();

/// Thrown for a bad flag, value or config file: the message names the key (and file and line).
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Raw values gathered from the command line: option name -> values, in the order given.
using RawOptions = std::vector<std::pair<std::string, std::vector<std::string>>>;

/// Builds the configuration: defaults, then the config file's keys (if `config_file`), then the
/// command line's. Also applies derived settings (the cgrw preset from width). Throws ConfigError.
[[nodiscard]] Config build_config(const std::optional<std::string>& config_file,
                                  const RawOptions& command_line);

/// The same with the config file's text given directly (no file is read, e.g. for fuzzing);
/// `source_name` stands for the file's path in messages, which are otherwise build_config's.
[[nodiscard]] Config build_config_from_text(std::string_view toml_text, const std::string& source_name,
                                            const RawOptions& command_line);

/// Applies one [[receiver]] table's keys to `config` (a copy of the shared settings), then the
/// derived settings as build_config() does. Throws ConfigError naming the file, line and key.
void apply_receiver_table(Config& config, const ReceiverTable& table);

}  // namespace gpsemu
