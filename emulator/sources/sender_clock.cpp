#include "emulator/sources/sender_clock.hpp"

#include <algorithm>
#include <cmath>

namespace gpsemu::sources {

UtcNs SenderClock::place(UtcNs arrival, double sender_time_s) {
  const std::chrono::nanoseconds sent{std::llround(sender_time_s * 1e9)};
  const std::chrono::nanoseconds offset = arrival.time_since_epoch() - sent;
  if (last_sender_time_s_ && sender_time_s <= *last_sender_time_s_) {
    // A datagram overtaken by a newer one (placed by the estimate, for the history to drop), or
    // a sender started again: its times begin afresh.
    if (*last_sender_time_s_ - sender_time_s <= kRestartS && !rising_.empty()) {
      return UtcNs{sent + std::min(offset, rising_.front().offset)};
    }
    reset();
  }
  last_sender_time_s_ = sender_time_s;
  while (!rising_.empty() && rising_.back().offset >= offset) rising_.pop_back();
  rising_.push_back({arrival, offset});
  // Arrivals are read in order, so the oldest are at the front; the pose just pushed never leaves.
  while (rising_.front().arrival < arrival - window_) rising_.pop_front();
  return UtcNs{sent + rising_.front().offset};
}

void SenderClock::reset() {
  rising_.clear();
  last_sender_time_s_.reset();
}

}  // namespace gpsemu::sources
