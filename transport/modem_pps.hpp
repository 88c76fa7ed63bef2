// PPS on a modem control line (RTS or DTR) of the serial output's own UART (`--pps modem:RTS`):
// wire it to the receiving computer's DCD or CTS, where the kernel's PPS line discipline (or
// gpsd/chrony) time-stamps it. Pseudo-terminals have no modem lines: refused at start-up.
#pragma once

#include <string>

#include "transport/pps.hpp"
#include "transport/serial_output.hpp"

namespace gpsemu::transport {

class ModemPps final : public PpsLine {
 public:
  /// Drives `line` of `serial`, which must outlive this object. Checks that the device has the
  /// line and sets it to the idle level; throws std::runtime_error naming the device otherwise.
  ModemPps(SerialOutput& serial, ModemLine line, PpsPolarity polarity);
  /// Leaves the line at its idle level.
  ~ModemPps() override;

  /// "modem RTS of serial:/dev/ttyUSB0@115200".
  [[nodiscard]] std::string describe() const override;

 protected:
  bool drive(bool level, std::string& error_text) override;

 private:
  SerialOutput& serial_;
  ModemLine line_;
};

}  // namespace gpsemu::transport
