// The one place the pipeline reads a Config: what the channels, the sink, the loop and replay
// need, in small settings structs. Everything downstream takes these, never the whole Config.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emulator/config/config.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/time.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/pps_timeline.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/replay/replay_options.hpp"
#include "emulator/sources/pose_source.hpp"

namespace gpsemu {

/// One receiver of a run: its channel, its outputs and how to make its pose source.
struct ReceiverSetup {
  ChannelSettings channel;
  OutputSettings outputs;
  std::string source_spec;  ///< --source as given ("sim:circle", "udp:5600")
  /// Makes the pose source (it refers to the channel's frame). Throws naming the spec.
  std::function<std::unique_ptr<sources::PoseSource>(const LocalFrame&, UtcNs first_epoch)> make_source;
};

/// The shared timeline and pacing of a run.
struct LoopSettings {
  double rate_hz = 1.0;
  std::chrono::nanoseconds latency{0};
  std::optional<UtcNs> start_time;
  /// Epochs to run (--duration x --rate); empty: until stopped.
  std::optional<std::int64_t> epochs;
  ClockSpec clock;  ///< kind fast for --fast
  PpsSettings pps;  ///< spec empty: no PPS line (always with --fast)
};

struct RunSettings {
  LoopSettings loop;
  std::vector<ReceiverSetup> receivers;  ///< one, or a fleet's (fleet_config.hpp)
};

/// The shared timeline and pacing.
[[nodiscard]] LoopSettings loop_settings(const Config& config);
/// Every receiver of `config` (its fleet expanded). Throws like receiver_configs().
[[nodiscard]] RunSettings run_settings(const Config& config);
/// `config`'s one receiver (the library facade).
[[nodiscard]] ReceiverSetup receiver_setup(const Config& config);

/// `gpsemu replay`'s settings.
struct ReplaySettings {
  replay::ReplayOptions options;
  bool fast = false;
  ClockSpec clock;
  std::optional<std::chrono::nanoseconds> duration;  ///< of log time
  std::chrono::nanoseconds latency{0};
  std::optional<UtcNs> start_time;
  OutputSettings outputs;  ///< rate and line check: set from the log (replayer.hpp)
};
[[nodiscard]] ReplaySettings replay_settings(const Config& config);

}  // namespace gpsemu
