// The one place the pipeline reads the configuration (config/settings.hpp, by scope): what the
// channels, the sink, the loop and replay's pacing need, in small settings structs. Everything
// downstream takes these.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emulator/config/settings.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/time.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/pps_timeline.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/sources/pose_source.hpp"

namespace gpsemu {

struct Config;

/// One receiver of a run: its channel, its outputs and how to make its pose source.
struct ReceiverSetup {
  ChannelSettings channel;
  OutputSettings outputs;
  bool sim_source = true;   ///< a simulator scenario (sim:...): the library may step it alone
  std::string source_text;  ///< --source as given ("sim:circle", "udp:5600")
  /// Makes the pose source (it refers to the channel's frame). Throws naming the spec.
  std::function<std::unique_ptr<sources::PoseSource>(const LocalFrame&, UtcNs first_epoch)> make_source;
  /// Checks the source against the clock (validate.hpp; the emulator checks every receiver before
  /// it opens anything). Throws std::invalid_argument.
  std::function<void()> check_source;
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
  std::vector<ReceiverSetup> receivers;  ///< one, or a fleet's
  std::optional<std::string> control_path;  ///< the control socket (--control unix:PATH)
  std::chrono::milliseconds control_idle_timeout{30000};  ///< its clients are closed after this long silent (0: never)
  /// Something watches the epochs (--ui, --control's watch and status, --status-every): the
  /// runner makes a ui::Hub.
  bool watched = false;
  std::chrono::nanoseconds status_every{0};  ///< --status-every (zero: never)
};

/// The shared timeline and pacing.
[[nodiscard]] LoopSettings loop_settings(const TimelineSettings& timeline);
/// One receiver on `timeline`.
[[nodiscard]] ReceiverSetup receiver_setup(const ReceiverSettings& receiver, const TimelineSettings& timeline);
/// Gives `channel` (receiver `i` of `receivers`) the faults of `scenario` that apply to it.
void add_faults(ChannelSettings& channel, const std::vector<faults::Fault>& scenario, std::size_t i, std::size_t receivers);
/// Every receiver of `config`, each with its faults.
[[nodiscard]] RunSettings run_settings(const Config& config);

/// How `gpsemu replay` paces and stops.
struct ReplayPacing {
  replay::ReplayOptions options;
  bool fast = false;
  std::optional<std::chrono::nanoseconds> duration;  ///< of log time
  std::chrono::nanoseconds latency{0};
  std::optional<UtcNs> start_time;
};
[[nodiscard]] ReplayPacing replay_pacing(const TimelineSettings& timeline, const ReplaySettings& replay);

}  // namespace gpsemu
