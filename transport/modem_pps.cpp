#include "transport/modem_pps.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace gpsemu::transport {

ModemPps::ModemPps(SerialOutput& serial, ModemLine line, PpsPolarity polarity)
    : PpsLine(polarity), serial_(serial), line_(line) {
  serial_.check_modem_line(line_);
  std::string error_text;
  if (!serial_.set_modem_line(line_, idle_level(), error_text)) {
    throw std::runtime_error(fmt::format("PPS {}: {}", describe(), error_text));
  }
}

ModemPps::~ModemPps() {
  std::string ignored;
  (void)serial_.set_modem_line(line_, idle_level(), ignored);
}

std::string ModemPps::describe() const {
  return fmt::format("modem {} of {}", to_string(line_), serial_.describe());
}

bool ModemPps::drive(bool level, std::string& error_text) { return serial_.set_modem_line(line_, level, error_text); }

}  // namespace gpsemu::transport
