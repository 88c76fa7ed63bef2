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

namespace gpsemu::transport {

class LogLimit {
 public:
  using Clock = std::chrono::steady_clock;
  /// At most `lines_per_second` lines in each window of one second (at least 1).
  explicit LogLimit(std::uint32_t lines_per_second = 5) : per_second_(lines_per_second == 0 ? 1 : lines_per_second) {}

  /// Whether a line may be written at `now`; when not, it is counted as suppressed.
  [[nodiscard]] bool admit(Clock::time_point now);
  /// Lines suppressed since the last line let through (and forgets them: the caller reports them).
  [[nodiscard]] std::uint64_t take_suppressed();
  /// Lines suppressed over the whole run.
  [[nodiscard]] std::uint64_t suppressed_total() const { return suppressed_total_; }

 private:
  std::uint32_t per_second_;
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
/// suppressed since the last one.
template <class... Args>
void log_limited(LogLimit& limit, spdlog::level::level_enum level, fmt::format_string<Args...> format, Args&&... args) {
  if (!spdlog::should_log(level)) return;
  if (!limit.admit(LogLimit::Clock::now())) return;
  spdlog::log(level, "{}{}", fmt::format(format, std::forward<Args>(args)...), suppressed_note(limit.take_suppressed()));
}

}  // namespace gpsemu::transport
