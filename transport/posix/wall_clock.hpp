// The wall clock: CLOCK_REALTIME (UTC, as the system keeps it), the one way the emulator, its
// transports and its tools read the time of day. Nanoseconds since the Unix epoch.
#pragma once

#include <time.h>

#include <chrono>

namespace gpsemu::posix {

/// A point on the wall clock (UTC), nanoseconds.
using WallTime = std::chrono::sys_time<std::chrono::nanoseconds>;

/// CLOCK_REALTIME now.
[[nodiscard]] WallTime wall_clock_now();

/// A timespec of CLOCK_REALTIME (a kernel time stamp, SO_TIMESTAMPNS) as a WallTime.
[[nodiscard]] constexpr WallTime to_wall_time(const timespec& ts) {
  return WallTime{std::chrono::seconds{ts.tv_sec} + std::chrono::nanoseconds{ts.tv_nsec}};
}

/// Seconds since the Unix epoch, for tools that compute in double.
[[nodiscard]] constexpr double to_unix_seconds(WallTime t) {
  return std::chrono::duration<double>(t.time_since_epoch()).count();
}

}  // namespace gpsemu::posix
