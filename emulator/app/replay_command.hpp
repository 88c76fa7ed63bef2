// `gpsemu replay LOG`: the command line of the replayer (replay/replayer.hpp), which sends a
// recorded NMEA log to the configured outputs paced by its own time fields.
#pragma once

#include <CLI/CLI.hpp>

#include "emulator/app/subcommands.hpp"

namespace gpsemu {

[[nodiscard]] Subcommand add_replay_command(CLI::App& app);

}  // namespace gpsemu
