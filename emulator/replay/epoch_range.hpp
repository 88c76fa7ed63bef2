// --from/--to (replay_options.hpp) applied to a log read in order, one epoch at a time, so a
// replay can skip to its range and stop at its end while streaming (log_stream.hpp). A time of
// day is the first epoch at or after it (--from), the last at or before it (--to, searched from
// --from), both on the log's timeline (across midnight too); an index is that epoch. What is
// wrong with a range is a std::invalid_argument naming the option ("from: ...", "to: ...") as
// soon as it shows: an index or time past the log's end once the end is reached.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "emulator/config/spec/replay_options.hpp"
#include "emulator/replay/replay_log.hpp"

namespace gpsemu::replay {

class RangeCursor {
 public:
  enum class Place { before, in, after };

  /// `first_log_time`: the log's first epoch's time on its timeline (where --from's time of day
  /// is looked for from). Throws when --to's index comes before --from's.
  RangeCursor(std::optional<LogPosition> from, std::optional<LogPosition> to, std::chrono::nanoseconds first_log_time);

  /// Where epoch `index` of the log (given in order, each at least once; again is the same
  /// answer) lies. Throws when --to's time comes before the range's first epoch, or --to's index
  /// before it.
  Place place(std::uint64_t index, const LogEpoch& epoch);
  /// The log ended after `epochs` epochs, the last at `last_log_time`: throws when --from was not
  /// reached, or --to's index is past the end.
  void at_end(std::uint64_t epochs, std::chrono::nanoseconds last_log_time) const;
  /// An index --to names that lies past `last_index` (an error if the log ends there).
  [[nodiscard]] bool to_index_beyond(std::uint64_t last_index) const;
  /// Starts again at the log's first epoch (--loop): the same range.
  void restart();

  /// The range's first epoch (once place() said in).
  [[nodiscard]] std::optional<std::uint64_t> first() const { return first_; }

 private:
  std::optional<LogPosition> from_, to_;
  std::chrono::nanoseconds first_log_time_;
  std::optional<std::uint64_t> first_;
  std::optional<std::chrono::nanoseconds> to_time_;  ///< --to's time on the timeline, once the range started
  std::optional<std::uint64_t> last_index_;
  Place last_place_ = Place::before;
};

}  // namespace gpsemu::replay
