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

}  // namespace

std::unique_ptr<PortLister> make_system_port_lister() { return std::make_unique<LibSerialPortLister>(); }

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
