// `gpsemu replay LOG`: reads the log, checks the options against it, opens the outputs and runs
// the replayer (emulator/replay/replayer.hpp) on the epoch loop.
#pragma once

#include <CLI/CLI.hpp>

#include "emulator/app/subcommands.hpp"

namespace gpsemu {

[[nodiscard]] Subcommand add_replay_command(CLI::App& app);

}  // namespace gpsemu
