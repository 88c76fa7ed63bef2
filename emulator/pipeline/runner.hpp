// The emulator's run: the receiver channels of a Config (one, or a fleet: fleet_config.hpp) as
// the producer of the one epoch loop (epoch_loop.hpp), their outputs in one sink (sink.hpp), the
// clock --clock names and, in real time, the PPS line on the same timeline: leading edge at each
// whole second S, the NMEA stamped S at S + latency after it, trailing edge at S + width.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "emulator/config/config.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/control_socket.hpp"
#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/pps_timeline.hpp"
#include "emulator/pipeline/run_settings.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/pipeline/timeline.hpp"
#include "transport/output.hpp"
#include "transport/pps.hpp"

namespace gpsemu {

struct RunStats {
  std::uint64_t epochs_emitted = 0;   ///< epochs formatted and handed to the outputs (each receiver's)
  std::uint64_t epochs_late_skipped = 0;  ///< epochs skipped because their time had long passed
  std::uint64_t clock_steps_back = 0;     ///< times the wall clock went back (the deadlines followed)
  std::uint64_t epochs_without_fix = 0;   ///< over all receivers
  /// Wake-ups while waiting: one an epoch (plus one a PPS edge) when no input arrives.
  std::uint64_t wakeups = 0;
  std::uint64_t waits_already_due = 0;  ///< deadlines that had passed when the loop came to wait for them
  std::uint64_t pps_pulses = 0;               ///< leading edges driven
  std::uint64_t pps_pulses_late_skipped = 0;  ///< pulses not sent: their second had passed by over half the width
  /// Worst time from a leading edge's whole second to the return of the call that drove it.
  std::chrono::nanoseconds pps_worst_edge_delay{0};
};

/// What a Runner writes to when the caller (a test) provides it instead of config.outputs/pps.
struct RunnerIo {
  std::vector<std::unique_ptr<transport::Output>> outputs;
  std::unique_ptr<transport::PpsLine> pps;  ///< none: no PPS
};

class ChannelSet;
namespace ui {
class Hub;
}

class Runner {
 public:
  /// Opens every receiver's source and outputs. Throws (std::exception with a clear message) when
  /// any of them cannot be set up: the caller exits with status 2, and no output file has been
  /// changed (they are truncated once everything is open: Sink::commit()).
  explicit Runner(const Config& config);
  /// One receiver writing to `io` instead of opening config.outputs and config.pps (tests:
  /// recording fakes).
  Runner(const Config& config, RunnerIo io);
  ~Runner();

  /// Runs until the duration is reached or `stop` becomes true. Returns the process exit status.
  int run(const std::atomic<bool>& stop);

  [[nodiscard]] const RunStats& stats() const { return stats_; }
  [[nodiscard]] std::size_t receivers() const { return sink_.receivers(); }
  [[nodiscard]] const ReceiverStats& receiver_stats(std::size_t i) const;
  /// Receiver i's outputs.
  [[nodiscard]] const std::vector<std::unique_ptr<transport::Output>>& outputs(std::size_t i = 0) const {
    return sink_.outputs(i);
  }
  /// What watches the epochs (--ui, --control, --status-every); null when nothing does.
  [[nodiscard]] ui::Hub* hub() const { return hub_.get(); }
  /// Epoch time minus wall time: 0, or the --start-time shift (whole seconds when PPS is on).
  [[nodiscard]] std::chrono::nanoseconds epoch_minus_wall() const { return timeline_.epoch_minus_wall; }

 private:
  Runner(RunSettings settings, std::optional<RunnerIo> io);
  void log_banner() const;
  void log_summary() const;

  LoopSettings loop_;
  Timeline timeline_;
  std::unique_ptr<ChannelSet> channels_;
  std::unique_ptr<ui::Hub> hub_;  ///< after the channels it reads
  std::unique_ptr<ControlSocket> control_;  ///< --control: after the channels it reaches
  Sink sink_;
  std::unique_ptr<transport::PpsLine> pps_line_;  ///< after the sink: a modem PPS line uses a serial output
  std::unique_ptr<PpsTimeline> pps_;
  std::unique_ptr<sources::PoseSource> fleet_time_;  ///< lockstep with many receivers: the slowest simulator's time
  std::unique_ptr<SystemClockIo> io_;  ///< every wait: the timer and the inputs
  std::unique_ptr<EpochClock> clock_;
  RunStats stats_;
};

}  // namespace gpsemu
