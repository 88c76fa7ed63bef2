#include "tools/timing/timing_inputs.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <termios.h>

#include <cerrno>
#include <regex>
#include <stdexcept>

#include <fmt/format.h>

#include "transport/posix/errors.hpp"
#include "transport/posix/sockets.hpp"

namespace gpsemu::timing {

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
  if (host_port.find(':') == std::string::npos) {
    throw std::invalid_argument(fmt::format("'{}': expected HOST:PORT", host_port));
  }
  const posix::Endpoint to = posix::parse_endpoint(host_port);
  // Connected blocking (a refused connection is told at once), then read without blocking.
  posix::UniqueFd fd = posix::connect_socket(
      {.host = to.host, .port = to.port, .blocking = true, .context = "cannot connect to " + host_port});
  ::fcntl(fd.get(), F_SETFL, O_NONBLOCK);
  return fd.release();
}

int open_udp(const std::string& host_port) {
  posix::Endpoint at = posix::parse_endpoint(host_port);
  if (host_port.find(':') == std::string::npos) at.host.clear();  // no host: every interface
  posix::UniqueFd fd = posix::bind_socket(
      {.host = at.host, .port = at.port, .type = SOCK_DGRAM, .context = "cannot bind udp " + host_port});
  // Kernel receive time stamps, and the count of datagrams our buffer dropped.
  if (const int err = posix::enable_datagram_stamps(fd.get()); err != 0) {
    throw std::runtime_error(fmt::format("udp {}: SO_TIMESTAMPNS: {}", host_port, posix::errno_text(err)));
  }
  return fd.release();
}

}  // namespace gpsemu::timing
