// Replay as a producer of epochs: a recorded NMEA log (replay_log.hpp), read as a stream with a
// bounded look-ahead (log_stream.hpp), sent epoch by epoch through
// the one epoch loop and sink (pipeline/epoch_loop.hpp, pipeline/sink.hpp), paced by the
// sentences' own time fields, not by a fixed delay per line:
//
// - Epoch i leaves at wall_0 + (log_time_i - log_time_first) / speed, on absolute deadlines
//   (a scaled clock that never skips), so nothing drifts; each epoch's bytes go out in one write,
//   unchanged. An epoch whose time went back is sent right after the previous one; a gap in the
//   log is a wait. Nothing is skipped when late: the worst delay is reported.
// - --from/--to pick a range (epoch_range.hpp: skipped to at start-up, ended while streaming),
//   --loop reads the file again from its start (one nominal period after the last epoch: the
//   timeline goes on; a pipe is read once, so --loop is refused for it), --duration stops after
//   that much log time, --fast sends without pacing.
// - --retime rewrites time and date fields (checksums recomputed): epoch i is stamped T_0 +
//   (log_time_i - log_time_first), where T_0 is --start-time, or the first whole-second shift
//   of the log's first time that lies in the future (its sub-second phase kept); without
//   --start-time the first epoch then leaves at T_0 + latency, as a live receiver's would.
// At the end the counts are logged (the log's as far as it was read: the whole log's when the
// replay reached its end): epochs and bytes sent, what the reader skipped (binary, bad
// checksums, malformed, comments), epochs without a time, gaps, steps back, rollovers; and, for
// a paced replay to a serial line, the epochs wider than the line carries at the replay's rate
// (the start-up check saw only the look-ahead window's widest).
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emulator/config/settings.hpp"
#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/run_settings.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/replay/epoch_range.hpp"
#include "emulator/replay/log_stream.hpp"
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
  /// Epochs wider than the slowest serial output carries at the replay's rate (paced replays).
  std::uint64_t epochs_over_line_budget = 0;
  bool to_past_the_end = false;  ///< the log ended before --to's index
};

class Replayer {
 public:
  /// `range`: what check_replay_options() returned for `log`, which it left at the range's first
  /// epoch. `io` paces and services (none: the system clock, polling the outputs' clients).
  /// `line_budget_bytes`: the widest epoch the slowest serial output carries (none: no serial).
  Replayer(const TimelineSettings& timeline, const ReplaySettings& replay, std::unique_ptr<LogStream>&& log,
           RangeCursor range, std::vector<std::unique_ptr<transport::Output>> outputs, ClockIo* io = nullptr,
           std::optional<std::size_t> line_budget_bytes = std::nullopt);
  /// The same, checking the options against the log first (throws std::invalid_argument naming
  /// the option).
  Replayer(const TimelineSettings& timeline, const ReplaySettings& replay, std::unique_ptr<LogStream> log,
           std::vector<std::unique_ptr<transport::Output>> outputs, ClockIo& io);
  ~Replayer();

  /// Sends the range (again and again with --loop) until done or `stop`. Returns 0, or 1 when
  /// every output is gone.
  int run(const std::atomic<bool>& stop);

  [[nodiscard]] const ReplayStats& stats() const { return stats_; }
  /// Retimed stamp of the range's first epoch (meaningful with --retime).
  [[nodiscard]] UtcNs first_stamp() const { return first_stamp_; }

 private:
  void log_summary() const;

  ReplayPacing settings_;
  std::unique_ptr<LogStream> log_;
  RangeCursor range_;
  Sink sink_;
  ClockIo* io_ = nullptr;  ///< none: the system clock, polling the outputs
  std::optional<std::size_t> line_budget_bytes_;
  UtcNs first_stamp_{};
  ReplayStats stats_;
};

/// Checks the options against the log: the clock (replay has its own pacing), --loop (a regular
/// file), and the --from/--to range: reads on to the range's first epoch (the epochs before it
/// are let go) and checks --to as far as the look-ahead window shows. Returns the range, `log`
/// left at its first epoch. Throws std::invalid_argument naming the option.
[[nodiscard]] RangeCursor check_replay_options(const TimelineSettings& timeline, const ReplaySettings& replay,
                                               LogStream& log);

/// Opens the receiver's outputs (--output, then --tee) for a replay of `log`, at the replay's
/// epoch rate; refuses a serial line that cannot carry the widest epoch of the look-ahead window
/// (paced replays).
[[nodiscard]] std::vector<std::unique_ptr<transport::Output>> open_replay_outputs(const ReceiverSettings& receiver,
                                                                                  const TimelineSettings& timeline,
                                                                                  const ReplaySettings& replay,
                                                                                  const LogStream& log);

/// The widest epoch (bytes) the slowest serial output of a paced replay carries at its rate
/// within the line budget margin; none without a serial output or with --fast.
[[nodiscard]] std::optional<std::size_t> replay_line_budget_bytes(const ReceiverSettings& receiver,
                                                                  const TimelineSettings& timeline,
                                                                  const ReplaySettings& replay, const LogStream& log);

}  // namespace gpsemu::replay
