#include "emulator/config/spec/clock_spec.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace gpsemu {

ClockSpec parse_clock_spec(std::string_view text) {
  if (text == "realtime") return {};
  if (text == "fast") return {ClockKind::fast, 1.0};
  if (text == "lockstep") return {ClockKind::lockstep, 1.0};
  if (text.rfind("scaled:", 0) == 0) {
    const std::string_view k = text.substr(7);
    double scale = 0.0;
    const auto [ptr, ec] = std::from_chars(k.data(), k.data() + k.size(), scale);
    if (k.empty() || ec != std::errc{} || ptr != k.data() + k.size() || !std::isfinite(scale)) {
      throw std::invalid_argument(fmt::format("clock '{}': K in scaled:K must be a number, e.g. scaled:2", text));
    }
    if (scale < 0.01 || scale > 1000.0) {
      throw std::invalid_argument(fmt::format("clock '{}': K in scaled:K must be from 0.01 to 1000", text));
    }
    return {ClockKind::scaled, scale};
  }
  throw std::invalid_argument(
      fmt::format("unknown clock '{}' (accepted: realtime, scaled:K, fast, lockstep)", text));
}

std::string to_string(const ClockSpec& spec) {
  switch (spec.kind) {
    case ClockKind::realtime: return "realtime";
    case ClockKind::fast: return "fast";
    case ClockKind::lockstep: return "lockstep";
    case ClockKind::scaled: return fmt::format("scaled:{}", spec.scale);
  }
  return "?";
}

}  // namespace gpsemu
