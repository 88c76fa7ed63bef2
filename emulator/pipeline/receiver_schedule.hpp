// When one receiver has epochs: on the run's grid (--rate) until its protocol's client asks for
// another solution period (protocol::PeriodChanged: a u-blox's CFG-RATE, CFG-VALSET
// RATE-MEAS/NAV); then on that solution grid (a u-blox aligns it to the reference time's week).
// The epoch loop's timeline is the merge of every receiver's schedule: it wakes once an epoch
// time, and a receiver with no epoch at that time sends nothing (a lone NMEA receiver: exactly
// the run's grid).
#pragma once

#include <cstdint>
#include <optional>

#include "emulator/model/time.hpp"
#include "emulator/protocol/receiver_protocol.hpp"

namespace gpsemu {

class ReceiverSchedule {
 public:
  /// On `grid`, from epoch `first_index`.
  ReceiverSchedule(const EpochGrid& grid, std::int64_t first_index)
      : grid_(&grid), index_(first_index), next_(grid.time_of(first_index)) {}

  /// The receiver's next epoch.
  [[nodiscard]] UtcNs next() const { return next_; }
  /// Moves past the epoch next() returned.
  void advance();
  /// From the epoch after `t` (the one being sent) on: the solutions of `grid`, or the run's grid
  /// again when empty.
  void follow(const std::optional<protocol::SolutionGrid>& grid, UtcNs t);
  /// The time between epochs now.
  [[nodiscard]] std::chrono::nanoseconds period() const;

 private:
  const EpochGrid* grid_;
  std::int64_t index_;  ///< on the run's grid: next_'s index
  std::optional<protocol::SolutionGrid> solutions_;
  UtcNs next_;
};

}  // namespace gpsemu
