// The man page gpsemu(1), in roff (man(7) macros), written from the CLI11 application gpsemu's
// main() parses: every option with its value and help, every subcommand with its arguments and
// options, plus the config file, the service and the exit status.
#pragma once

#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

namespace gpsemu::cli_doc {

/// Writes gpsemu.1 for `app` (gpsemu::make_command_line()->app); `version` goes into its footer.
void write_man_page(std::ostream& out, const CLI::App& app, const std::string& version);

}  // namespace gpsemu::cli_doc
