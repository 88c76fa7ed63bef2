#include "emulator/pipeline/timeline.hpp"

namespace gpsemu {

Timeline choose_timeline(double rate_hz, std::optional<UtcNs> start_time, UtcNs now, std::size_t receivers,
                         bool whole_seconds) {
  Timeline tl{EpochGrid(rate_hz)};
  const auto start_up =
      std::chrono::milliseconds(1) + std::chrono::milliseconds(2) * (static_cast<std::int64_t>(receivers) - 1);
  const std::int64_t wall_index = tl.grid.index_at_or_after(now + start_up);
  tl.first_index = start_time ? tl.grid.index_at_or_after(*start_time) : wall_index;
  const UtcNs first = tl.grid.time_of(tl.first_index);
  if (start_time && whole_seconds) {
    const auto phase = first - std::chrono::floor<std::chrono::seconds>(first);
    const UtcNs first_wall = std::chrono::ceil<std::chrono::seconds>(now + start_up - phase) + phase;
    tl.epoch_minus_wall = first - first_wall;
  } else {
    tl.epoch_minus_wall = first - tl.grid.time_of(wall_index);
  }
  return tl;
}

}  // namespace gpsemu
