#include "emulator/sources/make_source.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/sources/sim.hpp"
#include "emulator/sources/socket_source.hpp"
#include "emulator/sources/trajectory_source.hpp"

namespace gpsemu::sources {

std::unique_ptr<PoseSource> make_source(const Config& config, const LocalFrame& frame, UtcNs first_epoch) {
  const std::string& spec = config.source;
  if (config.clock.kind == ClockKind::lockstep && spec.rfind("udp:", 0) != 0 && spec.rfind("tcp:", 0) != 0) {
    throw std::invalid_argument(fmt::format("--clock lockstep follows a simulator's time stamps: it needs a udp: or "
                                            "tcp: source, not --source {}", spec));
  }
  if (spec.rfind("sim:", 0) == 0) return make_sim_source(spec.substr(4), config.sim, frame, first_epoch);
  if (spec.rfind("replay:", 0) == 0) return make_trajectory_source(spec.substr(7), frame, first_epoch);
  if (spec.rfind("udp:", 0) == 0 || spec.rfind("tcp:", 0) == 0) {
    const bool lockstep = config.clock.kind == ClockKind::lockstep;
    if (!lockstep && config.clock.kind != ClockKind::realtime) {
      throw std::invalid_argument(fmt::format("--source {}: a socket source runs on the wall clock (or, with --clock "
                                              "lockstep, on the simulator's); it cannot be used with --clock {}",
                                              spec, to_string(config.clock)));
    }
    // Poses are placed at their arrival time on the wall clock, so epochs must be on it too
    // (lockstep places them at --start-time or the first epoch + their t instead).
    if (!lockstep && (config.fast || config.start_time)) {
      throw std::invalid_argument(fmt::format("--source {}: a socket source runs on the wall clock; it cannot be "
                                              "combined with --fast or --start-time", spec));
    }
    SocketSourceOptions options;
    options.history.timeout = std::chrono::nanoseconds{std::llround(config.pose_timeout_s * 1e9)};
    options.history.horizon = std::chrono::nanoseconds{std::llround(config.pose_horizon_s * 1e9)};
    if (lockstep) options.sender_time_base = config.start_time.value_or(first_epoch);
    try {
      return make_socket_source(spec.substr(0, 3), spec.substr(4), frame, options);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("--source {}: {}", spec, e.what()));
    }
  }
  throw std::invalid_argument(fmt::format(
      "unknown pose source '{}' (accepted: sim:stationary, sim:line, sim:circle, sim:waypoints:FILE, "
      "replay:FILE.csv, udp:[HOST:]PORT, tcp:[HOST:]PORT)", spec));
}

}  // namespace gpsemu::sources
