#include "emulator/subcommands.hpp"

namespace gpsemu {

std::vector<Subcommand> add_subcommands(CLI::App& app) {
  std::vector<Subcommand> all;
  (void)app;
  // all.push_back(add_calibrate_command(app));  -- each subcommand adds its line here
  return all;
}

}  // namespace gpsemu
