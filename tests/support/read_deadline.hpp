// Test support: read a pty, serial line, socket or pipe with poll() and a deadline, no sleeps.
// One loop for every test that reads what the emulator wrote: until enough bytes came, until the
// line went quiet, until the test's own condition holds, or until the other side went away.
#pragma once

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

namespace gpsemu::test {

/// When read_with_deadline() stops, besides the end of the stream and the caller's condition:
/// {timeout}, {timeout, quiet} or {timeout, quiet or std::nullopt, max_bytes}.
struct ReadLimits {
  ReadLimits(std::chrono::milliseconds timeout_in, std::optional<std::chrono::milliseconds> quiet_in = std::nullopt,
             std::size_t max_bytes_in = std::numeric_limits<std::size_t>::max())
      : timeout(timeout_in), quiet(quiet_in), max_bytes(max_bytes_in) {}
  std::chrono::milliseconds timeout;               ///< at most this long in all
  std::optional<std::chrono::milliseconds> quiet;  ///< stop once nothing came for this long
  std::size_t max_bytes;                           ///< never read past this many bytes
};

struct ReadResult {
  std::string bytes;   ///< everything read
  bool ended = false;  ///< end of file, or a failed read (a pty whose other side closed: EIO)
  int error = 0;       ///< errno of a failed read, 0 if none
};

/// Reads `fd` (blocking or not) until `done(chunk)` returns true after a read, `limits` stop it,
/// or the stream ends. `done` sees each read's bytes as they arrive (one datagram per read on a
/// datagram socket); it may record them or their arrival time.
template <class Done>
ReadResult read_with_deadline(int fd, const ReadLimits& limits, Done done) {
  using Clock = std::chrono::steady_clock;
  ReadResult r;
  const auto deadline = Clock::now() + limits.timeout;
  while (r.bytes.size() < limits.max_bytes) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) break;
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min(left, limits.quiet.value_or(left)).count()));
    if (ready < 0 && errno == EINTR) continue;
    if (ready == 0 && limits.quiet) break;  // quiet for long enough
    if (ready <= 0) continue;
    char buf[65536];
    const ssize_t n = ::read(fd, buf, std::min(sizeof buf, limits.max_bytes - r.bytes.size()));
    if (n > 0) {
      const std::string_view chunk(buf, static_cast<std::size_t>(n));
      r.bytes.append(chunk);
      if (done(chunk)) break;
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    r.ended = true;
    r.error = n < 0 ? errno : 0;
    break;
  }
  return r;
}

inline ReadResult read_with_deadline(int fd, const ReadLimits& limits) {
  return read_with_deadline(fd, limits, [](std::string_view) { return false; });
}

/// Reads until `want` bytes came (never more) or `timeout` passed.
inline std::string read_exactly(int fd, std::size_t want,
                                std::chrono::milliseconds timeout = std::chrono::milliseconds(2000)) {
  return read_with_deadline(fd, {timeout, std::nullopt, want}).bytes;
}

/// Reads what arrives until nothing more came for `quiet`, `timeout` passed, or `want` bytes came.
inline std::string read_available(int fd, std::chrono::milliseconds quiet, std::chrono::milliseconds timeout,
                                  std::size_t want = std::numeric_limits<std::size_t>::max()) {
  return read_with_deadline(fd, {timeout, quiet, want}).bytes;
}

}  // namespace gpsemu::test
