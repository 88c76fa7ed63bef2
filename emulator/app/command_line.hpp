// The command line of gpsemu: one CLI11 application built from the option table (every flag of the
// emulator, also a key of the config file) and the subcommands. main() parses with it; the CLI
// reference generator (tools/cli_doc) walks the same application, so docs/cli.md lists exactly
// what `gpsemu --help` and `gpsemu SUBCOMMAND --help` accept.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "emulator/app/subcommands.hpp"
#include "emulator/config/config.hpp"

namespace gpsemu {

struct CommandLine {
  CLI::App app{"gpsemu: hardware-in-the-loop GPS receiver emulator (NMEA over a pty, file or stdout)", "gpsemu"};
  std::string config_file;                                   ///< --config FILE (empty: none)
  std::map<std::string, std::vector<std::string>> values;    ///< option name -> values as given
  std::map<std::string, CLI::Option*> options;               ///< option name -> its CLI11 option
  std::vector<Subcommand> subcommands;

  /// The options given on the command line, in the option table's order (after app.parse()).
  [[nodiscard]] RawOptions given() const;
};

/// Builds the whole command line (not movable: CLI11 keeps pointers into it).
[[nodiscard]] std::unique_ptr<CommandLine> make_command_line();

}  // namespace gpsemu
