#include "emulator/pipeline/control_socket.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "transport/posix/sockets.hpp"

namespace gpsemu {
namespace {

std::vector<faults::FaultTimeline*> timelines_of(ChannelSet& channels) {
  std::vector<faults::FaultTimeline*> out;
  for (std::size_t i = 0; i < channels.size(); ++i) out.push_back(&channels.channel(i).faults());
  return out;
}

posix::UnixLineServer::Messages messages() {
  return {faults::control_error(fmt::format("too many control clients (at most {})", posix::UnixLineServer::kMaxClients)),
          faults::control_error(
              fmt::format("line longer than {} bytes: ignored to its end", posix::UnixLineServer::kMaxLineBytes))};
}

/// The server for `spec`: a Unix socket, or a TCP port (its real port in its name when 0 was asked).
posix::UnixLineServer make_server(const std::string& spec) {
  if (spec.rfind("tcp:", 0) != 0) return posix::UnixLineServer(spec, messages());
  const posix::Endpoint e = posix::parse_endpoint(spec.substr(4));
  posix::SocketRequest request;
  request.host = e.host;
  request.port = e.port;
  request.context = fmt::format("control socket {}: cannot listen", spec);
  posix::UniqueFd fd = posix::listen_tcp(request, 8);
  const std::uint16_t port = posix::bound_port(fd.get());
  return posix::UnixLineServer(std::move(fd), "tcp:" + posix::host_port(e.host, port), messages());
}

}  // namespace

ControlSocket::ControlSocket(const std::string& spec, ChannelSet& channels)
    : control_(timelines_of(channels)), server_(make_server(spec)) {}

std::string parse_control_spec(const std::string& spec) {
  if (spec.rfind("unix:", 0) == 0 && spec.size() > 5) return spec.substr(5);
  if (spec.rfind("tcp:", 0) == 0) {
    try {
      const posix::Endpoint e = posix::parse_endpoint(spec.substr(4));
      return "tcp:" + posix::host_port(e.host, e.port);
    } catch (const std::invalid_argument& err) {
      throw std::invalid_argument(fmt::format("control: {}", err.what()));
    }
  }
  throw std::invalid_argument(
      fmt::format("control: expected unix:PATH or tcp:[HOST:]PORT, e.g. unix:/tmp/gpsemu.ctl or tcp:127.0.0.1:5010, got '{}'", spec));
}

std::string control_request(const std::string& spec, std::string_view line, std::chrono::milliseconds timeout) {
  if (spec.rfind("tcp:", 0) == 0) {
    const posix::Endpoint e = posix::parse_endpoint(spec.substr(4));
    return posix::tcp_request(e.host, e.port, line, timeout);
  }
  return posix::unix_request(spec.rfind("unix:", 0) == 0 ? spec.substr(5) : spec, line, timeout);
}

}  // namespace gpsemu
