#include "emulator/ui/ui_spec.hpp"

#include "transport/posix/sockets.hpp"

#include <charconv>
#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::ui {

HttpSettings parse_ui_spec(const std::string& spec) {
  HttpSettings out;
  std::string port = spec;
  if (const std::size_t colon = spec.rfind(':'); colon != std::string::npos) {
    out.host = spec.substr(0, colon);
    port = spec.substr(colon + 1);
    if (out.host.size() > 2 && out.host.front() == '[' && out.host.back() == ']') out.host = out.host.substr(1, out.host.size() - 2);
    if (out.host.empty()) throw std::invalid_argument(fmt::format("ui: expected [HOST:]PORT, e.g. 8080 or 0.0.0.0:8080, got '{}'", spec));
  }
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (port.empty() || ec != std::errc() || end != port.data() + port.size() || value > 65535) {
    throw std::invalid_argument(fmt::format("ui: expected [HOST:]PORT with PORT 0..65535, e.g. 8080, got '{}'", spec));
  }
  out.port = static_cast<std::uint16_t>(value);
  return out;
}

bool is_loopback(const std::string& host) { return posix::is_loopback_host(host); }

}  // namespace gpsemu::ui
