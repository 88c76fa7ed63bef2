// Scheduling settings for a real-time process as a user gives them (--realtime-priority,
// --lock-memory, --timer-slack): the value. transport/posix/realtime.hpp applies them.
#pragma once

#include <optional>

namespace gpsemu::posix {

struct RealtimeSettings {
  std::optional<int> fifo_priority;     ///< SCHED_FIFO priority 1..99; empty: normal scheduling
  bool lock_memory = false;             ///< mlockall(MCL_CURRENT | MCL_FUTURE): no page faults in the loop
  std::optional<long> timer_slack_ns;   ///< prctl(PR_SET_TIMERSLACK) in nanoseconds (1 = minimal; kernel default 50 000)
};

}  // namespace gpsemu::posix
