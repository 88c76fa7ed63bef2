#include "emulator/sources/make_source.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/sources/sim.hpp"
#include "emulator/sources/socket_source.hpp"

namespace gpsemu::sources {

std::unique_ptr<PoseSource> make_source(const Config& config, const LocalFrame& frame, UtcNs first_epoch) {
  const std::string& spec = config.source;
  if (spec.rfind("sim:", 0) == 0) return make_sim_source(spec.substr(4), config.sim, frame, first_epoch);
  if (spec.rfind("udp:", 0) == 0 || spec.rfind("tcp:", 0) == 0) {
    // Poses are placed at their arrival time on the wall clock, so epochs must be on it too.
    if (config.fast || config.start_time) {
      throw std::invalid_argument(fmt::format("--source {}: a socket source runs on the wall clock; it cannot be "
                                              "combined with --fast or --start-time", spec));
    }
    SocketSourceOptions options;
    options.history.timeout = std::chrono::nanoseconds{std::llround(config.pose_timeout_s * 1e9)};
    options.history.horizon = std::chrono::nanoseconds{std::llround(config.pose_horizon_s * 1e9)};
    try {
      return make_socket_source(spec.substr(0, 3), spec.substr(4), frame, options);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("--source {}: {}", spec, e.what()));
    }
  }
  throw std::invalid_argument(fmt::format(
      "unknown pose source '{}' (accepted: sim:stationary, sim:line, sim:circle, sim:waypoints:FILE, "
      "udp:[HOST:]PORT, tcp:[HOST:]PORT)", spec));
}

}  // namespace gpsemu::sources
