// The built-in simulator: analytic trajectories about the origin, as functions of the time since
// the first epoch. stationary (the report's single-point test), line (the report's straight-line
// drive), circle (a loop around a parking lot), waypoints (a CSV route driven at set speeds).
// Each gives the car's heading (yaw_deg): its direction of travel (held once it stops); the
// stationary car faces --sim-heading.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "emulator/model/geo.hpp"
#include "emulator/sources/pose_source.hpp"

namespace gpsemu::sources {

struct SimOptions {
  double speed_mps = 2.0;       ///< line/circle/waypoint speed (m/s), > 0
  double heading_deg = 90.0;    ///< line heading (and where the stationary car faces), degrees true (90 = east)
  double drive_time_s = 20.0;   ///< line: seconds of driving before the car stops
  double radius_m = 20.0;       ///< circle radius (metres), centred on the origin
  bool loop = false;            ///< waypoints: start over after the last waypoint
};

/// One waypoint in local metres and the speed to drive from it to the next.
struct Waypoint {
  Enu position_m;
  double speed_mps = 0.0;
};

/// Reads a waypoint CSV (see README "Waypoint files"). Throws std::runtime_error naming the file
/// and line of the first problem.
[[nodiscard]] std::vector<Waypoint> read_waypoints(const std::filesystem::path& path,
                                                   const LocalFrame& frame, double default_speed_mps);
/// The same from a stream; `name` stands for the file in messages.
[[nodiscard]] std::vector<Waypoint> read_waypoints(std::istream& in, const std::string& name,
                                                   const LocalFrame& frame, double default_speed_mps);

/// `name` is what follows "sim:" in --source: stationary, line, circle, waypoints:FILE.
/// Throws std::invalid_argument for an unknown scenario or bad option.
[[nodiscard]] std::unique_ptr<PoseSource> make_sim_source(const std::string& name,
                                                          const SimOptions& options,
                                                          const LocalFrame& frame, UtcNs start);

}  // namespace gpsemu::sources
