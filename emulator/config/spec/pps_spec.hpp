// A PPS line as a user writes it (--pps gpio:CHIP:LINE | modem:RTS | modem:DTR): the value, its
// parser and its text. The transport drives it (transport/pps.hpp).
#pragma once

#include <string>
#include <string_view>

namespace gpsemu::transport {

/// A modem control line that can carry a PPS pulse.
enum class ModemLine { rts, dtr };

[[nodiscard]] const char* to_string(ModemLine line);

/// A PPS line as a user writes it: `gpio:CHIP:LINE`, `modem:RTS`, `modem:DTR`.
struct PpsSpec {
  enum class Kind { gpio, modem };
  Kind kind = Kind::gpio;
  std::string chip;  ///< gpio: "/dev/gpiochip0", "gpiochip0", "0" or a chip label
  std::string line;  ///< gpio: line offset ("18") or line name ("GPIO18")
  ModemLine modem_line = ModemLine::rts;  ///< modem: which line of the serial output

  friend bool operator==(const PpsSpec&, const PpsSpec&) = default;
};

inline constexpr std::string_view kPpsSpecForms = "gpio:CHIP:LINE, modem:RTS, modem:DTR";

/// Parses a PPS spec. Throws std::invalid_argument naming the text and the accepted forms.
[[nodiscard]] PpsSpec parse_pps_spec(std::string_view text);
[[nodiscard]] std::string to_string(const PpsSpec& spec);

}  // namespace gpsemu::transport
