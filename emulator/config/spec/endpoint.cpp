#include "emulator/config/spec/endpoint.hpp"

#include <fmt/format.h>

#include <charconv>
#include <stdexcept>

namespace gpsemu::posix {

Endpoint parse_endpoint(std::string_view text) {
  const auto bad = [&](const char* why) {
    return std::invalid_argument(fmt::format("'{}' is not [HOST:]PORT: {}", text, why));
  };
  Endpoint e;
  std::string_view port = text;
  if (!text.empty() && text.front() == '[') {
    const auto close = text.find(']');
    if (close == std::string_view::npos || close + 1 >= text.size() || text[close + 1] != ':') {
      throw bad("an IPv6 host is written [ADDRESS]:PORT");
    }
    e.host = std::string(text.substr(1, close - 1));
    port = text.substr(close + 2);
  } else if (const auto colon = text.rfind(':'); colon != std::string_view::npos) {
    if (text.find(':') != colon) throw bad("an IPv6 host is written [ADDRESS]:PORT");
    e.host = std::string(text.substr(0, colon));
    port = text.substr(colon + 1);
  }
  if (e.host.empty()) throw bad("empty host");
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (port.empty() || ec != std::errc{} || end != port.data() + port.size() || value > 65535) {
    throw bad("the port must be a number from 0 to 65535");
  }
  e.port = static_cast<std::uint16_t>(value);
  return e;
}

std::string host_port(std::string_view host, std::uint16_t port) {
  return host.find(':') != std::string_view::npos ? fmt::format("[{}]:{}", host, port)
                                                  : fmt::format("{}:{}", host, port);
}

bool is_loopback_host(std::string_view host) {
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

}  // namespace gpsemu::posix
