#include "transport/serial_ports.hpp"

#include <fmt/format.h>
#include <libserialport.h>

#include <charconv>
#include <stdexcept>

namespace gpsemu::transport {

namespace {

std::string text_or_empty(const char* s) { return s ? std::string(s) : std::string(); }

class LibSerialPortLister final : public PortLister {
 public:
  std::vector<SerialPortInfo> list_ports() override {
    sp_port** list = nullptr;
    if (sp_list_ports(&list) != SP_OK) {
      char* message = sp_last_error_message();
      const std::string why = text_or_empty(message);
      sp_free_error_message(message);
      throw std::runtime_error(fmt::format("cannot list serial ports (libserialport): {}", why));
    }
    std::vector<SerialPortInfo> out;
    for (sp_port** p = list; *p != nullptr; ++p) {
      SerialPortInfo info;
      info.device = text_or_empty(sp_get_port_name(*p));
      info.description = text_or_empty(sp_get_port_description(*p));
      switch (sp_get_port_transport(*p)) {
        case SP_TRANSPORT_NATIVE:
          info.transport = "native";
          break;
        case SP_TRANSPORT_USB: {
          info.transport = "usb";
          int vid = 0;
          int pid = 0;
          if (sp_get_port_usb_vid_pid(*p, &vid, &pid) == SP_OK) {
            info.usb_vid = static_cast<std::uint16_t>(vid);
            info.usb_pid = static_cast<std::uint16_t>(pid);
          }
          info.usb_manufacturer = text_or_empty(sp_get_port_usb_manufacturer(*p));
          info.usb_product = text_or_empty(sp_get_port_usb_product(*p));
          info.usb_serial = text_or_empty(sp_get_port_usb_serial(*p));
          break;
        }
        case SP_TRANSPORT_BLUETOOTH:
          info.transport = "bluetooth";
          break;
        default:
          info.transport = "unknown";
          break;
      }
      out.push_back(std::move(info));
    }
    sp_free_port_list(list);
    return out;
  }
};

std::uint16_t parse_hex_id(std::string_view text, std::string_view whole, const char* what) {
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value, 16);
  if (text.empty() || text.size() > 4 || ec != std::errc{} || end != text.data() + text.size()) {
    throw std::invalid_argument(fmt::format(
        "'{}': the USB {} must be 1 to 4 hexadecimal digits (e.g. 0403:6001), got '{}'", whole, what, text));
  }
  return static_cast<std::uint16_t>(value);
}

}  // namespace

std::unique_ptr<PortLister> make_system_port_lister() { return std::make_unique<LibSerialPortLister>(); }

UsbSelector parse_usb_selector(std::string_view text) {
  UsbSelector s;
  const std::size_t first = text.find(':');
  if (first == std::string_view::npos) {
    throw std::invalid_argument(fmt::format("'{}': expected VID:PID[:SERIAL], e.g. 0403:6001", text));
  }
  const std::size_t second = text.find(':', first + 1);
  s.vid = parse_hex_id(text.substr(0, first), text, "vendor ID");
  s.pid = parse_hex_id(text.substr(first + 1, second == std::string_view::npos ? std::string_view::npos
                                                                                : second - first - 1),
                       text, "product ID");
  if (second != std::string_view::npos) {
    s.serial = std::string(text.substr(second + 1));
    if (s.serial.empty()) {
      throw std::invalid_argument(fmt::format("'{}': empty serial number after VID:PID:", text));
    }
  }
  return s;
}

std::string to_string(const UsbSelector& selector) {
  std::string out = fmt::format("{:04x}:{:04x}", selector.vid, selector.pid);
  if (!selector.serial.empty()) out += ":" + selector.serial;
  return out;
}

std::vector<SerialPortInfo> find_usb_ports(const std::vector<SerialPortInfo>& ports,
                                           const UsbSelector& selector) {
  std::vector<SerialPortInfo> out;
  for (const auto& p : ports) {
    if (p.usb_vid != selector.vid || p.usb_pid != selector.pid) continue;
    if (!selector.serial.empty() && p.usb_serial != selector.serial) continue;
    out.push_back(p);
  }
  return out;
}

UsbLookup lookup_usb_port(const std::vector<SerialPortInfo>& ports, const UsbSelector& selector) {
  const std::vector<SerialPortInfo> found = find_usb_ports(ports, selector);
  if (found.size() == 1) return {found.front().device, {}};
  UsbLookup result;
  if (found.empty()) {
    std::vector<std::string> usb;
    for (const auto& p : ports) {
      if (p.usb_vid) usb.push_back(describe_port(p));
    }
    result.problem = fmt::format("no USB serial adapter {} is connected ({}; `gpsemu ports` lists them)",
                                 to_string(selector),
                                 usb.empty() ? std::string("no USB serial adapters found")
                                             : "connected: " + fmt::format("{}", fmt::join(usb, "; ")));
    return result;
  }
  std::vector<std::string> names;
  for (const auto& p : found) names.push_back(describe_port(p));
  result.problem = fmt::format(
      "{} USB serial adapters match {}: {}; add the serial number to choose one (serial:usb:{:04x}:{:04x}:SERIAL)",
      found.size(), to_string(selector), fmt::join(names, "; "), selector.vid, selector.pid);
  return result;
}

std::string describe_port(const SerialPortInfo& port) {
  std::string out = port.device + " " + port.transport;
  if (port.usb_vid && port.usb_pid) out += fmt::format(" {:04x}:{:04x}", *port.usb_vid, *port.usb_pid);
  if (!port.usb_serial.empty()) out += " serial " + port.usb_serial;
  if (!port.description.empty()) out += " \"" + port.description + "\"";
  return out;
}

}  // namespace gpsemu::transport
