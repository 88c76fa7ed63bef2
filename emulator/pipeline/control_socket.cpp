#include "emulator/pipeline/control_socket.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu {
namespace {

std::vector<faults::FaultTimeline*> timelines_of(ChannelSet& channels) {
  std::vector<faults::FaultTimeline*> out;
  for (std::size_t i = 0; i < channels.size(); ++i) out.push_back(&channels.channel(i).faults());
  return out;
}

}  // namespace

ControlSocket::ControlSocket(const std::string& path, ChannelSet& channels)
    : control_(timelines_of(channels)),
      server_(path, {faults::control_error(fmt::format("too many control clients (at most {})",
                                                       posix::UnixLineServer::kMaxClients)),
                     faults::control_error(fmt::format("line longer than {} bytes: ignored to its end",
                                                       posix::UnixLineServer::kMaxLineBytes))}) {}

std::string parse_control_spec(const std::string& spec) {
  if (spec.rfind("unix:", 0) != 0 || spec.size() == 5)
    throw std::invalid_argument(fmt::format("control: expected unix:PATH, e.g. unix:/tmp/gpsemu.ctl, got '{}'", spec));
  return spec.substr(5);
}

}  // namespace gpsemu
