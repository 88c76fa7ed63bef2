#include "transport/pps.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <stdexcept>

namespace gpsemu::transport {


bool PpsLine::set(bool pulse_on) {
  const bool level = pulse_on != (polarity_ == PpsPolarity::active_low);
  std::string error_text;
  const bool ok = drive(level, error_text);
  pulse_on_ = pulse_on;
  if (ok) {
    ++(pulse_on ? stats_.leading_edges : stats_.trailing_edges);
    return true;
  }
  ++stats_.failures;
  log_limited(failure_log_, spdlog::level::warn, "PPS {}: {} edge not driven ({})", describe(),
              pulse_on ? "leading" : "trailing", error_text);
  return false;
}

PpsEdge first_pps_edge_at_or_after(PpsTime t, std::chrono::nanoseconds width) {
  const auto second = std::chrono::floor<std::chrono::seconds>(t);
  if (second == t) return {second, true};
  if (second + width >= t) return {second + width, false};
  return {second + std::chrono::seconds(1), true};
}

PpsEdge next_pps_edge(const PpsEdge& edge, std::chrono::nanoseconds width) {
  if (edge.leading) return {edge.time + width, false};
  return {std::chrono::floor<std::chrono::seconds>(edge.time) + std::chrono::seconds(1), true};
}

}  // namespace gpsemu::transport
