// The option table: every flag of the command line and key of the config file, its help text,
// and how its value sets the Config (config.cpp builds a Config with it). Internal to emulator/.
#pragma once

#include <vector>

#include "emulator/config/config.hpp"

namespace gpsemu {

/// The most receivers one process runs.
inline constexpr int kMaxReceivers = 1024;

/// Every option, in --help order.
[[nodiscard]] std::vector<OptionDef> make_option_table();

}  // namespace gpsemu
