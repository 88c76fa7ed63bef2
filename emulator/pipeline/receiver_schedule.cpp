#include "emulator/pipeline/receiver_schedule.hpp"

namespace gpsemu {

void ReceiverSchedule::advance() {
  if (solutions_) {
    next_ = solutions_->next_after(next_);
  } else {
    next_ = grid_->time_of(++index_);
  }
}

void ReceiverSchedule::follow(const std::optional<protocol::SolutionGrid>& grid, UtcNs t) {
  solutions_ = grid;
  if (solutions_) {
    next_ = solutions_->next_after(t);
  } else {
    index_ = grid_->index_at_or_after(t + std::chrono::nanoseconds{1});
    next_ = grid_->time_of(index_);
  }
}

std::chrono::nanoseconds ReceiverSchedule::period() const {
  return solutions_ ? solutions_->period : grid_->nominal_period();
}

}  // namespace gpsemu
