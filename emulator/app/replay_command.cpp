#include "emulator/app/replay_command.hpp"

#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "emulator/pipeline/realtime.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/replay/replayer.hpp"

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
            replay::ReplayLog log = replay::read_replay_log(*path);
            (void)replay::check_replay_options(config, log, *path);  // before any output is opened
            auto outputs = open_outputs(replay::replay_output_settings(config, log));
            replay::Replayer replayer(config, std::move(log), *path, std::move(outputs));
            // --realtime-priority, --lock-memory, --timer-slack: as for the emulator's loop.
            for (const std::string& line : apply_realtime_settings(config.realtime)) spdlog::info("{}", line);
            return replayer.run(stop);
          }};
}

}  // namespace gpsemu
