// The epoch timeline of a run: the UTC grid (--rate), the first epoch on it and how far epoch
// time is from wall time. Chosen once, by the one function below, for the emulator loop, the
// fleet and the library facade alike.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "emulator/model/time.hpp"

namespace gpsemu {

struct Timeline {
  EpochGrid grid;
  std::int64_t first_index = 0;
  /// Epoch time minus wall time: 0, or the --start-time shift (whole seconds with PPS).
  std::chrono::nanoseconds epoch_minus_wall{0};

  [[nodiscard]] UtcNs first_epoch() const { return grid.time_of(first_index); }
  /// The first epoch's time on the wall clock (its deadline without latency).
  [[nodiscard]] UtcNs first_wall() const { return first_epoch() - epoch_minus_wall; }
};

/// The first epoch: the next grid epoch after `now`, or the first at or after `start_time`. With
/// `start_time`, epoch times are shifted from the wall clock by a whole number of epochs, so the
/// sub-second phase of every epoch still matches the wall clock; with `whole_seconds` (PPS), by a
/// whole number of seconds, so the second an epoch is stamped with is the second its pulse marks.
/// Many receivers take a while to open (sockets, ptys, banners): the first epoch is one far enough
/// ahead that it is not already late when the loop starts (1 ms, and 2 ms a further receiver).
[[nodiscard]] Timeline choose_timeline(double rate_hz, std::optional<UtcNs> start_time, UtcNs now,
                                       std::size_t receivers = 1, bool whole_seconds = false);

}  // namespace gpsemu
