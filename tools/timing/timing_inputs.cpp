#include "tools/timing/timing_inputs.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <regex>
#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::timing {
namespace {

std::string errno_text() { return std::strerror(errno); }

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
  if (fd < 0) throw std::runtime_error(fmt::format("cannot open {}: {}", path, errno_text()));
  termios t{};
  if (tcgetattr(fd, &t) == 0) {
    cfmakeraw(&t);
    tcsetattr(fd, TCSANOW, &t);
  }
  return fd;
}

int open_tcp(const std::string& host_port) {
  const auto [host, port] = split_host_port(host_port, true);
  addrinfo hints{}, *res = nullptr;
  hints.ai_socktype = SOCK_STREAM;
  if (const int rc = getaddrinfo(host.c_str(), port.c_str(), &hints, &res); rc != 0) {
    throw std::runtime_error(fmt::format("cannot resolve {}: {}", host_port, gai_strerror(rc)));
  }
  const int fd = socket(res->ai_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int rc = fd < 0 ? -1 : connect(fd, res->ai_addr, res->ai_addrlen);
  const int err = errno;
  freeaddrinfo(res);
  if (rc != 0) {
    if (fd >= 0) ::close(fd);
    throw std::runtime_error(fmt::format("cannot connect to {}: {}", host_port, std::strerror(err)));
  }
  fcntl(fd, F_SETFL, O_NONBLOCK);
  return fd;
}

int open_udp(const std::string& host_port) {
  const auto [host, port] = split_host_port(host_port, false);
  addrinfo hints{}, *res = nullptr;
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  if (const int rc = getaddrinfo(host.empty() ? nullptr : host.c_str(), port.c_str(), &hints, &res); rc != 0) {
    throw std::runtime_error(fmt::format("udp {}: {}", host_port, gai_strerror(rc)));
  }
  const int fd = socket(res->ai_family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  const int one = 1;
  const int rc = fd < 0 ? -1 : bind(fd, res->ai_addr, res->ai_addrlen);
  const int err = errno;
  freeaddrinfo(res);
  if (rc != 0) {
    if (fd >= 0) ::close(fd);
    throw std::runtime_error(fmt::format("cannot bind udp {}: {}", host_port, std::strerror(err)));
  }
  if (setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one) != 0) {
    ::close(fd);
    throw std::runtime_error(fmt::format("udp {}: SO_TIMESTAMPNS: {}", host_port, errno_text()));
  }
  setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof one);  // datagrams our buffer dropped
  return fd;
}

}  // namespace gpsemu::timing
