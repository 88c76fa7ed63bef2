#include "tools/timing/timing_inputs.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <termios.h>

#include <cerrno>
#include <charconv>
#include <cstdint>
#include <regex>
#include <stdexcept>

#include <fmt/format.h>

#include "transport/posix/errors.hpp"
#include "transport/posix/sockets.hpp"

namespace gpsemu::timing {
namespace {

/// The port of a spec, 0..65535. Throws naming the spec.
std::uint16_t parse_port(const std::string& spec, const std::string& port) {
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (port.empty() || ec != std::errc{} || end != port.data() + port.size() || value > 65535) {
    throw std::invalid_argument(fmt::format("'{}': the port must be a number from 0 to 65535", spec));
  }
  return static_cast<std::uint16_t>(value);
}

/// Splits "[HOST:]PORT" / "HOST:PORT" / "[v6]:PORT" into host (may be empty) and port.
std::pair<std::string, std::string> split_host_port(const std::string& text, bool host_required) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos) {
    if (host_required) throw std::invalid_argument(fmt::format("'{}': expected HOST:PORT", text));
    return {"", text};
  }
  std::string host = text.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  return {host, text.substr(colon + 1)};
}

}  // namespace

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::device: return "device";
    case Kind::tcp: return "tcp";
    case Kind::udp: return "udp";
  }
  return "?";
}

std::string expand_template(const std::string& spec, int i) {
  static const std::regex field(R"(\{(?:(-?[0-9]+)\s*\+\s*)?i\})");
  std::string out;
  auto begin = spec.cbegin();
  std::smatch m;
  while (std::regex_search(begin, spec.cend(), m, field)) {
    out.append(begin, m[0].first);
    const long base = m[1].matched ? std::stol(m[1].str()) : 0;
    out += std::to_string(base + i);
    begin = m[0].second;
  }
  out.append(begin, spec.cend());
  if (out.find('{') != std::string::npos || out.find('}') != std::string::npos) {
    throw std::invalid_argument(fmt::format("'{}': templates are {{i}} and {{B+i}} (B an integer)", spec));
  }
  return out;
}

bool has_template(const std::string& spec) { return expand_template(spec, 0) != expand_template(spec, 1); }

int open_device(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(fmt::format("cannot open {}: {}", path, posix::errno_text(errno)));
  termios t{};
  if (tcgetattr(fd, &t) == 0) {
    cfmakeraw(&t);
    tcsetattr(fd, TCSANOW, &t);
  }
  return fd;
}

int open_tcp(const std::string& host_port) {
  const auto [host, port] = split_host_port(host_port, true);
  // Connected blocking (a refused connection is told at once), then read without blocking.
  posix::UniqueFd fd = posix::connect_socket(
      {.host = host, .port = parse_port(host_port, port), .blocking = true, .context = "cannot connect to " + host_port});
  ::fcntl(fd.get(), F_SETFL, O_NONBLOCK);
  return fd.release();
}

int open_udp(const std::string& host_port) {
  const auto [host, port] = split_host_port(host_port, false);
  posix::UniqueFd fd =
      posix::bind_socket({.host = host, .port = parse_port(host_port, port), .type = SOCK_DGRAM,
                          .context = "cannot bind udp " + host_port});
  // Kernel receive time stamps, and the count of datagrams our buffer dropped.
  if (const int err = posix::enable_datagram_stamps(fd.get()); err != 0) {
    throw std::runtime_error(fmt::format("udp {}: SO_TIMESTAMPNS: {}", host_port, posix::errno_text(err)));
  }
  return fd.release();
}

}  // namespace gpsemu::timing
