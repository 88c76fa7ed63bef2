// Rate-limited log lines for repeated events (spdlog's "at most once a second" habit, one helper
// for every such line): a LogLimit lets through at most N lines in each second and counts the
// others; the next line let through says how many similar lines were suppressed before it, so a
// flood of effects (a client toggling CFG-RATE, 100 000 CFG-RST) or of skipped epochs writes a few
// lines a second, never millions. The time is passed in (tests feed their own), std::chrono.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include <spdlog/spdlog.h>

namespace gpsemu {

class LogLimit {
 public:
  using Clock = std::chrono::steady_clock;
  /// At most `lines_per_second` lines in each window of one second (at least 1).
  explicit LogLimit(std::uint32_t lines_per_second = 5) : per_second_(lines_per_second == 0 ? 1 : lines_per_second) {}
  /// At most `lines` lines in each window of `window` (a line every 10 s: LogLimit(1, 10s)).
  LogLimit(std::uint32_t lines, std::chrono::nanoseconds window)
      : per_second_(lines == 0 ? 1 : lines), window_(window > std::chrono::nanoseconds::zero() ? window : std::chrono::seconds(1)) {}

  /// Whether a line may be written at `now`; when not, it is counted as suppressed.
  [[nodiscard]] bool admit(Clock::time_point now);
  /// Lines suppressed since the last line let through (and forgets them: the caller reports them).
  [[nodiscard]] std::uint64_t take_suppressed();
  /// Lines suppressed over the whole run.
  [[nodiscard]] std::uint64_t suppressed_total() const { return suppressed_total_; }

 private:
  std::uint32_t per_second_;  ///< lines a window
  std::chrono::nanoseconds window_{std::chrono::seconds(1)};
  Clock::time_point window_start_{};
  std::uint32_t in_window_ = 0;
  bool started_ = false;
  std::uint64_t suppressed_ = 0;
  std::uint64_t suppressed_total_ = 0;
};

/// Lines every LogLimit of the process suppressed (the run's summary says it).
[[nodiscard]] std::uint64_t log_lines_suppressed();

/// " (N similar lines suppressed)" for N > 0, else "".
[[nodiscard]] std::string suppressed_note(std::uint64_t suppressed);

/// Logs `format` at `level` when `limit` lets a line through now, with the count of the lines it
/// suppressed since the last one. Whether the line was written (a caller that reports a counter's
/// growth moves its "reported" mark only then). Every repeated line of the program goes through
/// here: effects, skipped epochs and pulses, failed writes of an output, a pty's or serial line's
/// read errors, answers and TX bytes dropped, clients refused.
template <class... Args>
bool log_limited(LogLimit& limit, spdlog::level::level_enum level, fmt::format_string<Args...> format, Args&&... args) {
  if (!spdlog::should_log(level)) return false;
  if (!limit.admit(LogLimit::Clock::now())) return false;
  spdlog::log(level, "{}{}", fmt::format(format, std::forward<Args>(args)...), suppressed_note(limit.take_suppressed()));
  return true;
}

}  // namespace gpsemu
