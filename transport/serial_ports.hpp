// Finding serial adapters by identity. A small interface over the system's list of serial ports
// (libserialport in production, a fake list in tests), and the pure lookup of a USB adapter by
// vendor ID, product ID and optionally serial number — which is how `serial:usb:VID:PID[:SERIAL]`
// re-finds an adapter that was unplugged and came back under another name (ttyUSB0 -> ttyUSB1).
// libserialport is used for listing only: it cannot open pseudo-terminals, so I/O is termios.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/config/spec/output_spec.hpp"

namespace gpsemu::transport {

/// One serial port as the system reports it.
struct SerialPortInfo {
  std::string device;       ///< what to open: "/dev/ttyUSB0", "/dev/ttyS0", "/dev/ttyACM0"
  std::string transport;    ///< "usb", "native" (board UART), "bluetooth" or "unknown"
  std::string description;  ///< human-readable, e.g. "FT232R USB UART - FT232R USB UART"
  std::optional<std::uint16_t> usb_vid;  ///< USB vendor ID (usb only)
  std::optional<std::uint16_t> usb_pid;  ///< USB product ID (usb only)
  std::string usb_manufacturer;          ///< "FTDI" (usb only; may be empty)
  std::string usb_product;               ///< "FT232R USB UART" (usb only; may be empty)
  std::string usb_serial;                ///< "A10KZ3QF" (usb only; empty when the adapter has none)

  friend bool operator==(const SerialPortInfo&, const SerialPortInfo&) = default;
};

/// Lists the serial ports present right now.
class PortLister {
 public:
  virtual ~PortLister() = default;
  /// Never throws for a port it cannot describe (it is listed with what is known); throws
  /// std::runtime_error only when the list itself cannot be read.
  [[nodiscard]] virtual std::vector<SerialPortInfo> list_ports() = 0;
};

/// The system's ports through libserialport (sysfs on Linux).
[[nodiscard]] std::unique_ptr<PortLister> make_system_port_lister();

/// The USB ports of `ports` that `selector` matches, in the order given.
[[nodiscard]] std::vector<SerialPortInfo> find_usb_ports(const std::vector<SerialPortInfo>& ports,
                                                         const UsbSelector& selector);

/// Where a selector points now.
struct UsbLookup {
  std::optional<std::string> device;  ///< set when exactly one port matches
  std::string problem;                ///< otherwise: none or several match, in words, naming them
};

/// Looks `selector` up in `ports`: exactly one match gives its device; none or several give a
/// message naming the selector, the candidates and what to do.
[[nodiscard]] UsbLookup lookup_usb_port(const std::vector<SerialPortInfo>& ports,
                                        const UsbSelector& selector);

/// "/dev/ttyUSB0 usb 0403:6001 A10KZ3QF FTDI FT232R USB UART": one line for listings and messages.
[[nodiscard]] std::string describe_port(const SerialPortInfo& port);

}  // namespace gpsemu::transport
