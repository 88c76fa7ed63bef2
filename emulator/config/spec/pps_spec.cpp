#include "emulator/config/spec/pps_spec.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace gpsemu::transport {

const char* to_string(ModemLine line) { return line == ModemLine::rts ? "RTS" : "DTR"; }

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
