// Builds the pose source a typed spec names (source_spec.hpp): a simulator scenario, a recorded
// trajectory or a socket fed by an external simulator.
#pragma once

#include <memory>

#include "emulator/model/geo.hpp"
#include "emulator/model/time.hpp"
#include "emulator/sources/pose_source.hpp"
#include "emulator/sources/sim.hpp"
#include "emulator/sources/socket_source.hpp"
#include "emulator/sources/source_spec.hpp"

namespace gpsemu::sources {

/// `sim` applies to sim: scenarios, `socket` to udp:/tcp: sources (its history options to mavlink: ones too); `first_epoch` is the time of the
/// run's first epoch. Throws std::invalid_argument / std::runtime_error naming the source spec on
/// failure (an unknown scenario, a missing file, a port in use).
[[nodiscard]] std::unique_ptr<PoseSource> make_source(const SourceSpec& spec, const SimOptions& sim,
                                                      const SocketSourceOptions& socket, const LocalFrame& frame,
                                                      UtcNs first_epoch);

}  // namespace gpsemu::sources
