#include "emulator/sources/make_source.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "emulator/sources/sim.hpp"

namespace gpsemu::sources {

std::unique_ptr<PoseSource> make_source(const Config& config, const LocalFrame& frame, UtcNs first_epoch) {
  const std::string& spec = config.source;
  if (spec.rfind("sim:", 0) == 0) return make_sim_source(spec.substr(4), config.sim, frame, first_epoch);
  throw std::invalid_argument(fmt::format(
      "unknown pose source '{}' (accepted: sim:stationary, sim:line, sim:circle, sim:waypoints:FILE)", spec));
}

}  // namespace gpsemu::sources
