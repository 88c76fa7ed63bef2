#include "emulator/config/spec/control_spec.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "emulator/config/spec/endpoint.hpp"

namespace gpsemu {

std::string parse_control_spec(const std::string& spec) {
  if (spec.rfind("unix:", 0) == 0 && spec.size() > 5) return spec.substr(5);
  if (spec.rfind("tcp:", 0) == 0) {
    try {
      const posix::Endpoint e = posix::parse_endpoint(spec.substr(4));
      if (!posix::is_loopback_host(e.host)) {
        // Faults from any host that reaches it, with no token: refused (the bench view asks a token off loopback).
        throw std::invalid_argument(fmt::format(
            "control: '{}' would take faults from any host that reaches {} with no token; bind a loopback address "
            "(tcp:127.0.0.1:{}) and reach it from elsewhere through ssh -L, or use --ui, which asks a token off loopback",
            spec, e.host, e.port));
      }
      return "tcp:" + posix::host_port(e.host, e.port);
    } catch (const std::invalid_argument& err) {
      throw std::invalid_argument(fmt::format("control: {}", err.what()));
    }
  }
  throw std::invalid_argument(
      fmt::format("control: expected unix:PATH or tcp:[HOST:]PORT, e.g. unix:/tmp/gpsemu.ctl or tcp:127.0.0.1:5010, got '{}'", spec));
}

}  // namespace gpsemu
