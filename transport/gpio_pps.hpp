// PPS on a GPIO line through libgpiod (`--pps gpio:CHIP:LINE`; Debian 12 ships libgpiod 1.6, whose
// C API this uses): the line is requested as an output ("gpsemu-pps") for the emulator's
// lifetime and driven at each edge. Wire it to the receiving computer's PPS input (a GPIO with
// the pps-gpio overlay on a Raspberry Pi, or DCD of a UART).
#pragma once

#include <string>

#include "transport/pps.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace gpsemu::transport {

class GpioPps final : public PpsLine {
 public:
  /// Opens `chip` ("/dev/gpiochip0", "gpiochip0", "0" or a chip label) and requests `line` (an
  /// offset such as "18", or a line name) as an output at the idle level. Throws
  /// std::runtime_error with one message naming the chip and line: no such chip, no such line,
  /// permission denied, line in use (naming its consumer).
  GpioPps(const std::string& chip, const std::string& line, PpsPolarity polarity);
  /// Leaves the line at its idle level and releases it.
  ~GpioPps() override;

  /// "gpio gpiochip0 line 18".
  [[nodiscard]] std::string describe() const override { return description_; }

 protected:
  bool drive(bool level, std::string& error_text) override;

 private:
  gpiod_chip* chip_ = nullptr;
  gpiod_line* line_ = nullptr;
  std::string description_;
};

}  // namespace gpsemu::transport
