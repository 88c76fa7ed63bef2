// Replay as a producer of epochs: a recorded NMEA log (replay_log.hpp) sent epoch by epoch through
// the one epoch loop and sink (pipeline/epoch_loop.hpp, pipeline/sink.hpp), paced by the
// sentences' own time fields, not by a fixed delay per line:
//
// - Epoch i leaves at wall_0 + (log_time_i - log_time_first) / speed, on absolute deadlines
//   (a scaled clock that never skips), so nothing drifts; each epoch's bytes go out in one write,
//   unchanged. An epoch whose time went back is sent right after the previous one; a gap in the
//   log is a wait. Nothing is skipped when late: the worst delay is reported.
// - --from/--to pick a range, --loop starts over (one nominal period after the last epoch),
//   --duration stops after that much log time, --fast sends without pacing.
// - --retime rewrites time and date fields (checksums recomputed): epoch i is stamped T_0 +
//   (log_time_i - log_time_first), where T_0 is --start-time, or the first whole-second shift
//   of the log's first time that lies in the future (its sub-second phase kept); without
//   --start-time the first epoch then leaves at T_0 + latency, as a live receiver's would.
// At the end the counts are logged: epochs and bytes sent, what the reader skipped (binary,
// bad checksums, malformed, comments), epochs without a time, gaps, steps back, rollovers.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "emulator/config/settings.hpp"
#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/run_settings.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/replay/replay_log.hpp"
#include "transport/output.hpp"

namespace gpsemu::replay {

struct ReplayStats {
  std::uint64_t epochs_sent = 0;
  std::uint64_t sentences_sent = 0;
  std::uint64_t bytes_sent = 0;
  std::uint64_t passes = 0;                 ///< times the range was started (--loop)
  /// Latest an epoch was handed to the outputs after its deadline (an epoch whose time went back:
  /// after the previous epoch's deadline).
  std::chrono::nanoseconds worst_delay{0};
  std::chrono::nanoseconds total_delay{0};  ///< sum of the delays (for the mean)
};

class Replayer {
 public:
  /// Checks the options against the log (range, clock); throws std::invalid_argument naming the
  /// option. `io` paces and services; `outputs` receive the epochs.
  Replayer(const TimelineSettings& timeline, const ReplaySettings& replay, ReplayLog log, std::string log_name,
           std::vector<std::unique_ptr<transport::Output>> outputs, ClockIo& io);
  /// The same, waiting on the system clock and polling the outputs' clients.
  Replayer(const TimelineSettings& timeline, const ReplaySettings& replay, ReplayLog log, std::string log_name,
           std::vector<std::unique_ptr<transport::Output>> outputs);
  ~Replayer();

  /// Sends the range (again and again with --loop) until done or `stop`. Returns 0.
  int run(const std::atomic<bool>& stop);

  [[nodiscard]] const ReplayStats& stats() const { return stats_; }
  [[nodiscard]] const EpochRange& range() const { return range_; }
  /// Retimed stamp of the range's first epoch (meaningful with --retime).
  [[nodiscard]] UtcNs first_stamp() const { return first_stamp_; }

 private:
  void log_summary() const;

  ReplayPacing settings_;
  ReplayLog log_;
  std::string name_;
  Sink sink_;
  ClockIo* io_ = nullptr;  ///< none: the system clock, polling the outputs
  EpochRange range_;
  UtcNs first_stamp_{};
  ReplayStats stats_;
};

/// Checks the options against the log: the clock (replay has its own pacing) and the --from/--to
/// range, which it returns. Throws std::invalid_argument naming the option.
[[nodiscard]] EpochRange check_replay_options(const TimelineSettings& timeline, const ReplaySettings& replay,
                                              const ReplayLog& log, const std::string& log_name);

/// Opens the receiver's outputs (--output, then --tee) for a replay of `log`, at the replay's
/// epoch rate; refuses a serial line that cannot carry the log's widest epoch (paced replays).
[[nodiscard]] std::vector<std::unique_ptr<transport::Output>> open_replay_outputs(const ReceiverSettings& receiver,
                                                                                  const TimelineSettings& timeline,
                                                                                  const ReplaySettings& replay,
                                                                                  const ReplayLog& log);

}  // namespace gpsemu::replay
