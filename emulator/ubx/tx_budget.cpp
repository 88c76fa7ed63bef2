// The u-blox TX buffer on a slow line (see tx_budget.hpp).
#include "emulator/ubx/tx_budget.hpp"

#include <algorithm>
#include <cstddef>

#include "emulator/ubx/frame.hpp"
#include "nmea/line_budget.hpp"

namespace gpsemu::ubx {
namespace {

/// Length of the message starting at `at`.
std::size_t message_length(const std::string& epoch, std::size_t at) {
  const std::size_t left = epoch.size() - at;
  if (epoch[at] == '$') {
    const std::size_t end = epoch.find('\n', at);
    return end == std::string::npos ? left : end + 1 - at;
  }
  if (left >= frame_overhead_bytes && static_cast<std::uint8_t>(epoch[at]) == sync1 &&
      static_cast<std::uint8_t>(epoch[at + 1]) == sync2) {
    const std::size_t payload = static_cast<std::uint8_t>(epoch[at + 4]) |
                                (static_cast<std::size_t>(static_cast<std::uint8_t>(epoch[at + 5])) << 8);
    return std::min(left, payload + frame_overhead_bytes);
  }
  // Neither: up to the next message start.
  for (std::size_t k = at + 1; k < epoch.size(); ++k) {
    if (epoch[k] == '$' || static_cast<std::uint8_t>(epoch[k]) == sync1) return k - at;
  }
  return left;
}

}  // namespace

std::size_t line_bytes_per_period(std::uint32_t baud, std::chrono::nanoseconds period) {
  return nmea::line_bytes_per_period(baud, period);  // baud / 10 bytes a second, whole bytes
}

TxDrops fit_epoch_to_line(std::string& epoch, std::size_t budget_bytes) {
  TxDrops drops;
  if (epoch.size() <= budget_bytes) return drops;
  std::size_t kept = 0;  // epoch[0, kept) is what goes out
  for (std::size_t at = 0; at < epoch.size();) {
    const std::size_t n = message_length(epoch, at);
    if (kept + n <= budget_bytes) {
      // Moving left within the string: a forward copy never reads what it has overwritten.
      if (kept != at) std::copy(epoch.begin() + static_cast<std::ptrdiff_t>(at),
                                epoch.begin() + static_cast<std::ptrdiff_t>(at + n),
                                epoch.begin() + static_cast<std::ptrdiff_t>(kept));
      kept += n;
    } else {
      ++drops.messages;
      drops.bytes += n;
    }
    at += n;
  }
  epoch.resize(kept);
  return drops;
}

}  // namespace gpsemu::ubx
