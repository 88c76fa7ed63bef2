#include "emulator/app/replay_command.hpp"

#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "emulator/config/config.hpp"
#include "emulator/config/config_options.hpp"
#include "emulator/replay/replayer.hpp"
#include "transport/posix/realtime.hpp"

namespace gpsemu {
namespace {

/// `gpsemu replay --help` lists the options a replay reads (they are the main options, parsed
/// before or after LOG), from the one option table: replay's own, then the shared ones.
std::string options_footer() {
  std::string text = "Options (before or after LOG; also keys of --config FILE):\n";
  auto line = [&text](const OptionDef& o) {
    const std::string flag = o.value_name.empty() ? "--" + o.name : "--" + o.name + " " + o.value_name;
    text += fmt::format("  {:<31} {}\n", flag, o.help);
  };
  for (const OptionDef& o : option_table()) {
    if (o.scope == OptionScope::replay) line(o);
  }
  for (const char* name : {"output", "tee", "start-time", "duration", "fast", "log-level", "realtime-priority",
                           "lock-memory", "timer-slack"}) {
    if (const OptionDef* o = find_option(name)) line(*o);
  }
  return text + "Example: gpsemu replay drive.nmea --speed 10 --from 12:00:00 --output pty:/tmp/gps";
}

}  // namespace

Subcommand add_replay_command(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand(
      "replay",
      "send a recorded NMEA log epoch by epoch, paced by its own time fields (binary, bad checksums and "
      "comments skipped): --speed, --loop, --from/--to, --retime, --fast, --output, --tee");
  sub->add_option("log", *path, "NMEA log (a receiver's raw stream, a gpsd log, a --tee file)")
      ->required()
      ->option_text("LOG");
  sub->footer(options_footer());
  return {sub, [path](const Config& config, const std::atomic<bool>& stop) {
            using namespace replay;
            auto log = std::make_unique<LogStream>(std::filesystem::path(*path));  // its first window: bad logs stop here
            RangeCursor range = check_replay_options(config.timeline, config.replay, *log);  // before any output
            std::vector<std::unique_ptr<transport::Output>> outputs =
                open_replay_outputs(config.receiver(), config.timeline, config.replay, *log);
            const auto budget = replay_line_budget_bytes(config.receiver(), config.timeline, config.replay, *log);
            Replayer replayer(config.timeline, config.replay, std::move(log), std::move(range), std::move(outputs),
                              nullptr, budget);
            // --realtime-priority, --lock-memory, --timer-slack: as for the emulator's loop.
            for (const std::string& line : posix::apply_realtime_settings(config.process.realtime)) spdlog::info("{}", line);
            return replayer.run(stop);
          }};
}

}  // namespace gpsemu
