// The options of `gpsemu replay` (replayer.hpp), kept in Config so they come from the one
// option table (command line and TOML file): speed, loop, range and retiming.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

namespace gpsemu::replay {

/// A place in a log: a UTC time of day (as written in the log's sentences) or an epoch index
/// (0 = the log's first epoch).
struct LogPosition {
  std::variant<std::chrono::nanoseconds, std::int64_t> value;  ///< time since midnight, or index

  [[nodiscard]] bool is_time_of_day() const { return value.index() == 0; }
  friend bool operator==(const LogPosition&, const LogPosition&) = default;
};

/// Parses "hh:mm:ss", "hh:mm:ss.ss" (a time of day) or "N" (an epoch index). Throws
/// std::invalid_argument naming `key` and the accepted forms.
[[nodiscard]] LogPosition parse_log_position(const std::string& key, const std::string& text);
/// "12:00:05.500" or "epoch 12".
[[nodiscard]] std::string to_string(const LogPosition& position);

struct ReplayOptions {
  double speed = 1.0;                ///< playback speed factor (0.1..100): 10 sends 1 s of log in 100 ms
  bool loop = false;                 ///< start over after the last epoch of the range
  std::optional<LogPosition> from;   ///< first epoch sent (default: the log's first)
  std::optional<LogPosition> to;     ///< last epoch sent, included (default: the log's last)
  bool retime = false;               ///< rewrite time and date fields to the present / --start-time
};

}  // namespace gpsemu::replay
