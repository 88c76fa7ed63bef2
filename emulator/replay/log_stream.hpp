// A recorded NMEA log read as a stream, for `gpsemu replay`: the file is read in chunks of
// kReadChunkBytes through nmea::StreamReader, cut into epochs as it comes (the rules are in
// replay_log.hpp) and placed on the log's timeline; only a window of epochs ahead is kept
// (kLookAheadEpochs epochs and kLookAheadBytes bytes of sentences, whichever is reached first),
// so memory stays flat whatever the log's size.
//
// What needs more than the window is settled at start-up, reading no more than it must:
// - the nominal period is the median positive spacing of the first kPeriodSpacings spacings of
//   consecutive timed epochs (all of them in a shorter log; 1 s when there is none);
// - untimed epochs before the first timed one are placed before it, one period apart.
// Both come from the window when it holds them (nearly always). When it does not (a log whose
// first kLookAheadEpochs epochs have no time, or too few spacings), a regular file is scanned
// from its start by a second reader that keeps only the spacings (no epochs); a pipe cannot be
// read twice: its period is the median of the spacings in the window, and a pipe whose window
// holds no timed epoch after untimed ones is refused.
// A regular file can be read again from its start (--loop), the same epochs on the same
// timeline; a pipe or FIFO is read once. The counts are the log's once it was read to its end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "emulator/replay/replay_log.hpp"

namespace gpsemu::replay {

/// Bytes read from the log at a time.
inline constexpr std::size_t kReadChunkBytes = 64 * 1024;
/// Epochs read ahead at most, and bytes of their sentences at most (at least one epoch is kept).
inline constexpr std::size_t kLookAheadEpochs = 1024;
inline constexpr std::size_t kLookAheadBytes = std::size_t{1} << 20;
/// Spacings between timed epochs the nominal period is the median of.
inline constexpr std::size_t kPeriodSpacings = 256;

class EpochSplitter;  // bytes to epochs (log_stream.cpp)

class LogStream {
 public:
  /// Opens a log file (a regular file, or a FIFO/pipe read once) and reads its first window.
  /// Throws std::runtime_error naming the file when it cannot be read, holds no NMEA sentence (with
  /// what it skipped), has only oversized epochs, or is a pipe whose first window places nothing.
  explicit LogStream(const std::filesystem::path& path);
  /// A log held in memory (tests, fuzzing): the same reader over `bytes`, which must outlive it.
  /// Never throws for its content.
  LogStream(std::string_view bytes, std::string name);
  ~LogStream();
  LogStream(const LogStream&) = delete;
  LogStream& operator=(const LogStream&) = delete;

  /// The next epoch, placed on the log's timeline; nullptr at the end of the log. Valid until pop().
  [[nodiscard]] const LogEpoch* peek();
  /// Moves the next epoch into `epoch` (when given) and goes past it; false at the end of the log.
  bool pop(LogEpoch* epoch = nullptr);
  /// Index in the log of the next epoch (0 for the first; again 0 after rewind()).
  [[nodiscard]] std::uint64_t position() const { return position_; }
  /// The epochs read ahead (the next one first).
  [[nodiscard]] const std::deque<LogEpoch>& window() const { return window_; }

  /// Reads the log again from its start (a regular file or memory). Counts stay the first pass's.
  void rewind();
  [[nodiscard]] bool can_rewind() const { return seekable_; }

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] std::chrono::nanoseconds period() const { return period_; }
  /// Spacings the period is the median of (fewer than kPeriodSpacings: the log has no more).
  [[nodiscard]] std::size_t period_spacings() const { return period_spacings_; }
  /// The log's first epoch's time on its timeline (the reference for --from times of day).
  [[nodiscard]] std::chrono::nanoseconds first_log_time() const { return first_log_time_; }
  /// What was skipped and the timeline's counts: the whole log's once ended().
  [[nodiscard]] const LogCounts& counts() const { return first_pass_ ? first_pass_->counts : pass_.counts; }
  /// Epochs cut so far (handed out and in the window), and whether the log was read to its end
  /// (the first pass's, after rewind()).
  [[nodiscard]] std::uint64_t epochs_read() const { return first_pass_ ? first_pass_->epochs : pass_.epochs; }
  [[nodiscard]] bool ended() const { return first_pass_ ? first_pass_->ended : pass_.ended; }
  /// Bytes read from the log so far (the first pass's, after rewind()).
  [[nodiscard]] std::uint64_t bytes_read() const { return first_pass_ ? first_pass_->bytes : pass_.bytes; }

 private:
  struct Source;
  void start();
  /// Reads chunks until the window is full or the log ends.
  void fill();
  /// Reads one chunk into cut_ (the last epoch too at the end of the log); false at the end.
  bool read_chunk();
  [[nodiscard]] bool window_full() const;
  /// Settles the period and the first timed epoch (header comment) from the first window.
  void settle_timeline();
  /// Places the epochs cut_ holds on the timeline and moves them into the window.
  void place_cut();

  std::string name_;
  std::unique_ptr<Source> source_;
  bool seekable_ = false;
  std::uint64_t offset_ = 0;  ///< next byte to read (regular files and memory)
  std::unique_ptr<EpochSplitter> splitter_;
  std::string chunk_;  ///< the bytes read last
  std::deque<LogEpoch> window_;
  std::size_t window_bytes_ = 0;
  std::deque<LogEpoch> cut_;  ///< cut, not yet placed (placed at once, but for the first window)
  bool settled_ = false;
  std::uint64_t position_ = 0;
  /// What a pass read and counted.
  struct Pass {
    LogCounts counts;
    std::uint64_t epochs = 0;
    std::uint64_t bytes = 0;
    bool ended = false;
  };
  Pass pass_;
  std::optional<Pass> first_pass_;  ///< kept at rewind()
  std::chrono::nanoseconds period_{std::chrono::seconds(1)};
  std::size_t period_spacings_ = 0;
  std::chrono::nanoseconds first_log_time_{0};
  /// Placement state: whole days added, the previous timed time of day and log time, the
  /// previous epoch's log time, untimed epochs still to come before the first timed one.
  std::int64_t day_ = 0;
  std::optional<std::chrono::nanoseconds> previous_tod_;
  std::optional<std::chrono::nanoseconds> previous_timed_;
  std::optional<std::chrono::nanoseconds> previous_log_time_;
  std::uint64_t leading_untimed_ = 0;
  std::chrono::nanoseconds first_timed_log_time_{0};
};

}  // namespace gpsemu::replay
