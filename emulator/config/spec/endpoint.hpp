// A host and port as a user writes them ("[HOST:]PORT"): the value, its parser and its text. Pure
// (no socket is opened here; transport/posix/sockets.hpp resolves and opens them).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace gpsemu::posix {

/// A host and port to listen on, bind or send to.
struct Endpoint {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
};

/// Parses "[HOST:]PORT": HOST defaults to 127.0.0.1, an IPv6 literal goes in brackets
/// ("[::1]:5005"), PORT is 0..65535. Throws std::invalid_argument naming the text.
[[nodiscard]] Endpoint parse_endpoint(std::string_view text);

/// Whether `host` names this machine's loopback only: localhost, ::1 or 127.x.y.z.
[[nodiscard]] bool is_loopback_host(std::string_view host);

/// "127.0.0.1:5005", or "[::1]:5005" for an IPv6 literal (a host holding ':').
[[nodiscard]] std::string host_port(std::string_view host, std::uint16_t port);

}  // namespace gpsemu::posix
