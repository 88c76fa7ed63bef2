// Scheduling settings for a real-time process (the emulator's loop, gpsemu-timing's reader): a
// SCHED_FIFO priority, locked memory and the smallest timer slack, so an epoch's bytes leave (or
// are stamped) at their deadline even on a loaded machine.
// Each is best effort: where the process is not permitted (no CAP_SYS_NICE / RLIMIT_RTPRIO, no
// CAP_IPC_LOCK / RLIMIT_MEMLOCK), it says so once and the emulator runs on without it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "emulator/config/spec/realtime_settings.hpp"

namespace gpsemu::posix {

/// Applies `settings` to the calling process (thread) and returns one line per setting saying what
/// was done or why not (for the log); never throws for a refused permission.
[[nodiscard]] std::vector<std::string> apply_realtime_settings(const RealtimeSettings& settings);

}  // namespace gpsemu::posix
