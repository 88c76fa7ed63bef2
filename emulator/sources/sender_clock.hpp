// Where a pose that carries its sender's own time `t` holds on our clock (UTC), outside lockstep.
//
// A pose's arrival time is only as good as the moment it was read: UDP datagrams carry the
// kernel's stamp, but TCP lines are stamped when gpsemu reads them, so after a late read (a loaded
// vehicle computer, gpsemu descheduled for 100 ms) a burst of queued poses would all hold at the read
// time and the epoch before it would interpolate towards a pose 100 ms old. The sender's own times say
// how the poses were spaced. A pose is placed at t + the smallest (arrival - t) among the sender's
// poses that arrived in the last `window`: the least delayed recent pose sets the offset between the
// two clocks, every pose holds no later than its arrival, the newest of a burst at most at its
// arrival and the others by their own spacing before it. A sender clock off ours by any constant is
// absorbed; one that drifts costs at most window x drift (0.5 s x 1% = 5 ms). A `t` a little older
// than the newest (a reordered datagram) is placed by the estimate without changing it; one more
// than kRestartS older (a restarted simulator) starts the estimate afresh.
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>
#include <optional>

#include "emulator/model/time.hpp"

namespace gpsemu::sources {

class SenderClock {
 public:
  static constexpr double kRestartS = 1.0;

  explicit SenderClock(std::chrono::nanoseconds window = std::chrono::milliseconds(500)) : window_(window) {}

  /// The time a pose sent at `sender_time_s` (its own clock, seconds) and read at `arrival` holds at.
  [[nodiscard]] UtcNs place(UtcNs arrival, double sender_time_s);
  /// Forgets the estimate (another sender, or the history cleared).
  void reset();

 private:
  struct Sample {
    UtcNs arrival;
    std::chrono::nanoseconds offset;  ///< arrival - t
  };
  std::chrono::nanoseconds window_;
  std::deque<Sample> rising_;  ///< the window's running minimum: offsets increasing front to back
  std::optional<double> last_sender_time_s_;
};

}  // namespace gpsemu::sources
