#include "transport/pps.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <stdexcept>

namespace gpsemu::transport {

const char* to_string(ModemLine line) { return line == ModemLine::rts ? "RTS" : "DTR"; }

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

PpsSpec parse_pps_spec(std::string_view text) {
  const auto reject = [&](std::string_view why) {
    return std::invalid_argument(
        fmt::format("invalid PPS spec '{}': {}; accepted forms: {}", text, why, kPpsSpecForms));
  };
  PpsSpec spec;
  if (text.substr(0, 5) == "gpio:") {
    const std::string_view rest = text.substr(5);
    const std::size_t colon = rest.rfind(':');
    if (colon == std::string_view::npos || colon == 0 || colon + 1 == rest.size()) {
      throw reject("gpio needs a chip and a line: gpio:/dev/gpiochip0:18 (or a line name)");
    }
    spec.kind = PpsSpec::Kind::gpio;
    spec.chip = std::string(rest.substr(0, colon));
    spec.line = std::string(rest.substr(colon + 1));
    return spec;
  }
  if (text.substr(0, 6) == "modem:") {
    const std::string_view line = text.substr(6);
    spec.kind = PpsSpec::Kind::modem;
    if (line == "RTS" || line == "rts") {
      spec.modem_line = ModemLine::rts;
    } else if (line == "DTR" || line == "dtr") {
      spec.modem_line = ModemLine::dtr;
    } else {
      throw reject("the modem line must be RTS or DTR (the outputs of a UART)");
    }
    return spec;
  }
  throw reject("unknown PPS kind");
}

std::string to_string(const PpsSpec& spec) {
  if (spec.kind == PpsSpec::Kind::gpio) return fmt::format("gpio:{}:{}", spec.chip, spec.line);
  return fmt::format("modem:{}", to_string(spec.modem_line));
}

}  // namespace gpsemu::transport
