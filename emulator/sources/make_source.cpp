#include "emulator/sources/make_source.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "emulator/sources/mavlink_source.hpp"
#include "emulator/sources/trajectory_source.hpp"

namespace gpsemu::sources {

std::unique_ptr<PoseSource> make_source(const SourceSpec& spec, const SimOptions& sim,
                                        const SocketSourceOptions& socket, const LocalFrame& frame,
                                        UtcNs first_epoch) {
  switch (spec.kind) {
    case SourceKind::sim: return make_sim_source(spec.scenario, sim, frame, first_epoch);
    case SourceKind::replay: return make_trajectory_source(spec.path, frame, first_epoch);
    case SourceKind::udp:
    case SourceKind::tcp: return make_socket_source(spec.kind == SourceKind::udp, spec.endpoint, frame, socket);
    case SourceKind::mavlink_udp:
    case SourceKind::mavlink_tcp:
      return make_mavlink_source(spec.kind == SourceKind::mavlink_udp, spec.endpoint, frame, socket.history);
  }
  throw std::invalid_argument(fmt::format("unknown pose source '{}'", spec.text));
}

}  // namespace gpsemu::sources
