// NAV-PVT flags3 lastCorrectionAge (u-blox F9 interface description): the age of the differential
// corrections as a 4-bit range code. Header-only, pure.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

namespace gpsemu::rtk {

/// 0 not available; 1 for age < 1 s, 2 for 1..2 s, 3 for 2..5 s, 4 for 5..10 s, 5 for 10..15 s,
/// 6 for 15..20 s, 7 for 20..30 s, 8 for 30..45 s, 9 for 45..60 s, 10 for 60..90 s,
/// 11 for 90..120 s, 12 for >= 120 s.
[[nodiscard]] inline std::uint32_t last_correction_age_code(const std::optional<double>& age_s) {
  if (!age_s) return 0;
  static constexpr std::array<double, 11> kUpperS{1, 2, 5, 10, 15, 20, 30, 45, 60, 90, 120};
  std::uint32_t code = 1;
  for (const double upper : kUpperS) {
    if (*age_s < upper) return code;
    ++code;
  }
  return code;
}

}  // namespace gpsemu::rtk
