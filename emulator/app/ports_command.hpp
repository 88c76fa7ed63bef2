// `gpsemu ports`: lists the serial ports of this machine (libserialport) with their USB
// description, VID:PID and serial number, and the output spec that selects each by identity
// (`serial:usb:VID:PID[:SERIAL]`, which survives the adapter coming back under another name).
#pragma once

#include <CLI/CLI.hpp>

#include "emulator/app/subcommands.hpp"

namespace gpsemu {

[[nodiscard]] Subcommand add_ports_command(CLI::App& app);

}  // namespace gpsemu
