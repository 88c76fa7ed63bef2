// Time types and the UTC epoch grid: epochs at whole seconds + j/rate (1 Hz: whole seconds;
// 10 Hz: .0 .1 .2 ...), or every N seconds for rates below 1 Hz.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

namespace gpsemu {

using UtcNs = std::chrono::sys_time<std::chrono::nanoseconds>;

/// Whether a UTC time must say so: `optional` also takes "2024-05-01 12:00:00" (no suffix, read as
/// UTC); `required` (what --start-time takes) refuses it, so a local time is never mistaken for UTC.
enum class UtcSuffix { optional, required };

/// Parses "2024-05-01T12:00:00Z", "2024-05-01T12:00:00.5Z", "2024-05-01 12:00:00" (UTC; a trailing
/// Z or +00:00 is accepted, other offsets are rejected). Throws std::invalid_argument.
[[nodiscard]] UtcNs parse_iso8601_utc(std::string_view text, UtcSuffix suffix = UtcSuffix::optional);
[[nodiscard]] std::string format_iso8601_utc(UtcNs time);

class EpochGrid {
 public:
  /// `rate_hz`: a whole number of epochs per second (1..50), or a rate below 1 Hz whose period is
  /// a whole number of seconds (0.5, 0.25, 0.2, 0.1). Throws std::invalid_argument otherwise.
  explicit EpochGrid(double rate_hz);

  /// Index of the first epoch at or after `t` (epoch indices count from 1970-01-01T00:00:00Z).
  [[nodiscard]] std::int64_t index_at_or_after(UtcNs t) const;
  [[nodiscard]] UtcNs time_of(std::int64_t index) const;
  [[nodiscard]] double rate_hz() const { return rate_hz_; }
  [[nodiscard]] std::chrono::nanoseconds nominal_period() const;

 private:
  double rate_hz_;
  std::int64_t per_second_ = 0;  ///< epochs per second (rates >= 1 Hz)
  std::int64_t period_s_ = 0;    ///< seconds per epoch (rates < 1 Hz)
};

}  // namespace gpsemu
