#include "emulator/app/subcommands.hpp"

#include "emulator/app/calibration_commands.hpp"
#include "emulator/app/ports_command.hpp"
#include "emulator/app/replay_command.hpp"

namespace gpsemu {

std::vector<Subcommand> add_subcommands(CLI::App& app) {
  std::vector<Subcommand> all;
  // each subcommand adds its line here
  all.push_back(add_base_command(app));
  all.push_back(add_calibrate_command(app));
  all.push_back(add_compare_command(app));
  all.push_back(add_ctl_command(app));
  all.push_back(add_judge_command(app));
  all.push_back(add_ports_command(app));
  all.push_back(add_profiles_command(app));
  all.push_back(add_replay_command(app));
  return all;
}

}  // namespace gpsemu
