// Bash completion for gpsemu, written from the CLI11 application gpsemu's main() parses: the flags
// of gpsemu and of the subcommand being typed, the subcommand names, file names where a value or
// argument is a file (value names FILE, LOG, PATH), and the fixed values a help text lists as
// "a | b | c" (--noise, --fix-quality, --log-level).
#pragma once

#include <ostream>

#include <CLI/CLI.hpp>

namespace gpsemu::cli_doc {

/// Writes the completion script (function _gpsemu, `complete -F _gpsemu gpsemu`).
void write_bash_completion(std::ostream& out, const CLI::App& app);

}  // namespace gpsemu::cli_doc
