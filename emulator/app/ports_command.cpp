#include "emulator/app/ports_command.hpp"

#include <fmt/format.h>

#include <cstdio>

#include "transport/serial_ports.hpp"

namespace gpsemu {

Subcommand add_ports_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "ports", "list serial ports (board UARTs, USB adapters) with USB description, VID:PID and serial "
               "number, and the --output spec that finds each adapter again after a replug");
  return {sub, [](const Config&, const std::atomic<bool>&) {
            const auto ports = transport::make_system_port_lister()->list_ports();
            if (ports.empty()) {
              std::fputs("no serial ports found\n", stdout);
              return 0;
            }
            std::string out = fmt::format("{:<22} {:<9} {:<9} {:<16} {}\n", "DEVICE", "TYPE", "VID:PID",
                                          "SERIAL", "DESCRIPTION");
            for (const auto& p : ports) {
              const bool usb = p.usb_vid && p.usb_pid;
              out += fmt::format("{:<22} {:<9} {:<9} {:<16} {}\n", p.device, p.transport,
                                 usb ? fmt::format("{:04x}:{:04x}", *p.usb_vid, *p.usb_pid) : "-",
                                 p.usb_serial.empty() ? "-" : p.usb_serial, p.description);
              if (usb) {
                transport::UsbSelector s{*p.usb_vid, *p.usb_pid, p.usb_serial};
                out += fmt::format("{:<22} use: --output serial:usb:{}@BAUD\n", "", to_string(s));
              }
            }
            std::fputs(out.c_str(), stdout);
            return 0;
          }};
}

}  // namespace gpsemu
