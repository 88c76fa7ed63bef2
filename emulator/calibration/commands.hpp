// The `gpsemu calibrate LOG` and `gpsemu compare LOG` subcommands (see calibrate.hpp for what
// they compute). calibrate writes the config file (to -o FILE, or to standard output with the
// summary on standard error) and prints a summary; compare prints the log and every calibrated
// model side by side with their scores, and can write the series as CSV for plots.
#pragma once

#include <CLI/CLI.hpp>

#include "emulator/app/subcommands.hpp"

namespace gpsemu::calibration {

[[nodiscard]] Subcommand add_calibrate_command(CLI::App& app);
[[nodiscard]] Subcommand add_compare_command(CLI::App& app);

}  // namespace gpsemu::calibration
