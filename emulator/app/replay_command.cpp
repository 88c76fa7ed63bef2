#include "emulator/app/replay_command.hpp"

#include <memory>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "emulator/config/config.hpp"
#include "emulator/replay/replayer.hpp"
#include "transport/posix/realtime.hpp"

namespace gpsemu {

Subcommand add_replay_command(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand(
      "replay",
      "send a recorded NMEA log epoch by epoch, paced by its own time fields (binary, bad checksums and "
      "comments skipped): --speed, --loop, --from/--to, --retime, --fast, --output, --tee");
  sub->add_option("log", *path, "NMEA log (a receiver's raw stream, a gpsd log, a --tee file)")
      ->required()
      ->option_text("LOG");
  return {sub, [path](const Config& config, const std::atomic<bool>& stop) {
            using namespace replay;
            ReplayLog log = read_replay_log(*path);
            (void)check_replay_options(config.timeline, config.replay, log, *path);  // before any output is opened
            std::vector<std::unique_ptr<transport::Output>> outputs =
                open_replay_outputs(config.receiver(), config.timeline, config.replay, log);
            Replayer replayer(config.timeline, config.replay, std::move(log), *path, std::move(outputs));
            // --realtime-priority, --lock-memory, --timer-slack: as for the emulator's loop.
            for (const std::string& line : posix::apply_realtime_settings(config.process.realtime)) spdlog::info("{}", line);
            return replayer.run(stop);
          }};
}

}  // namespace gpsemu
