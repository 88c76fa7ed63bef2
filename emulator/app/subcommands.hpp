// Subcommands of gpsemu besides the emulator itself (base, calibrate, compare, replay, ports, ...).
// Each lives in its own file and registers here; the main options (--output, --seed, ...) are
// parsed for them too, before or after the subcommand's name.
#pragma once

#include <atomic>
#include <functional>
#include <vector>

#include <CLI/CLI.hpp>

namespace gpsemu {

struct Config;  // config/config.hpp

struct Subcommand {
  CLI::App* app = nullptr;                     ///< the parsed subcommand (true when given)
  /// Returns the exit status; throws for bad input (exit 2). `stop` becomes true on SIGINT/SIGTERM.
  std::function<int(const Config&, const std::atomic<bool>& stop)> run;
};

/// `gpsemu base`: a simulated RTK base station writing RTCM3 (base_command.cpp).
[[nodiscard]] Subcommand add_base_command(CLI::App& app);
/// `gpsemu ctl PATH ...`: the control socket's client (ctl_command.cpp).
[[nodiscard]] Subcommand add_ctl_command(CLI::App& app);
/// `gpsemu profiles [NAME]`: the receiver profiles (profiles_command.cpp).
[[nodiscard]] Subcommand add_profiles_command(CLI::App& app);

/// Adds every subcommand to `app`. Add a line here for a new one.
[[nodiscard]] std::vector<Subcommand> add_subcommands(CLI::App& app);

}  // namespace gpsemu
