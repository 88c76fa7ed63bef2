// Trajectory replay, `--source replay:FILE.csv`: a recorded truth trajectory (a logged drive, a
// simulator's output) run through the receiver model and noise like any other source. Pure: the
// truth at an epoch is interpolated from the file, so the same file, seed and start time give
// byte-identical NMEA (with --fast and --start-time too).
//
// CSV: a header line names the columns, in any order; '#' starts a comment line; blank lines are
// ignored; spaces around values are ignored.
//   time      exactly one of
//     time_s     seconds from the first epoch (0 = the first epoch: --start-time or the next
//                epoch after now); any start, strictly increasing
//     utc        absolute UTC time, ISO 8601 (2024-05-01T12:00:00.25Z), strictly increasing
//   position  exactly one of
//     lat_deg,lon_deg[,alt_m]       degrees (WGS84), metres above MSL (absent: the origin's)
//     east_m,north_m[,up_m]         metres about --origin (x_m,y_m,z_m accepted for the same)
//   velocity  optional: ve_mps,vn_mps[,vu_mps] East/North/Up, metres per second. Without them
//             the velocity is the track's: constant along each segment between two rows.
//   yaw_deg   optional: true heading of the vehicle body, degrees clockwise from north, within
//             +-360 (interpolated the shorter way round); without it no heading (HDT/THS empty).
//   pitch_deg, roll_deg  optional: the body's pitch (within +-90) and roll (within +-180),
//             degrees, interpolated linearly; without them 0 (level).
// Values are limited as for socket poses (pose_message.hpp): local coordinates within 1e7 m,
// altitude -1e4..1e6 m, velocity components within 1e4 m/s.
// At least two rows. Between rows the position (and velocity) is interpolated linearly; before
// the first row the receiver reports no fix; after the last row the run ends.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emulator/model/geo.hpp"
#include "emulator/sources/pose_source.hpp"

namespace gpsemu::sources {

/// One row of a trajectory, placed in time.
struct TrajectoryPoint {
  UtcNs time{};
  Enu position_m;                   ///< East/North/Up about the origin (metres)
  std::optional<Enu> velocity_mps;  ///< when the file has velocity columns
  std::optional<double> yaw_deg;    ///< true heading (degrees, [0, 360)), when the file has yaw_deg
  Tilt tilt;                        ///< pitch_deg, roll_deg columns (degrees), 0 without them
};

/// A trajectory in time order, with the file's description for the banner.
struct Trajectory {
  std::vector<TrajectoryPoint> points;
  bool absolute_time = false;  ///< utc column (else time_s from the first epoch)
  std::string path;
};

/// Reads a trajectory CSV (format above). `first_epoch` is time_s = 0. Throws std::runtime_error
/// naming the file and line ("drive.csv:7: ...") of the first problem, or the file when it cannot
/// be opened or holds fewer than two rows.
[[nodiscard]] Trajectory read_trajectory_csv(const std::filesystem::path& path, const LocalFrame& frame,
                                             UtcNs first_epoch);
/// The same from a stream; `name` stands for the file's path in messages and in Trajectory::path.
[[nodiscard]] Trajectory read_trajectory_csv(std::istream& in, const std::string& name, const LocalFrame& frame,
                                             UtcNs first_epoch);

class TrajectorySource final : public PoseSource {
 public:
  /// Throws std::invalid_argument when the trajectory has fewer than two points.
  explicit TrajectorySource(Trajectory trajectory);

  /// Interpolated truth; nothing before the first point or after the last.
  [[nodiscard]] std::optional<Truth> truth_at(UtcNs t) override;
  [[nodiscard]] std::string describe() const override;
  /// After the last point.
  [[nodiscard]] bool ended_at(UtcNs t) const override { return t > trajectory_.points.back().time; }

 private:
  Trajectory trajectory_;
};

/// `--source replay:FILE`: reads the file and builds the source. Throws std::runtime_error (see
/// read_trajectory_csv), and when the whole trajectory lies before `first_epoch`.
[[nodiscard]] std::unique_ptr<PoseSource> make_trajectory_source(const std::filesystem::path& path,
                                                                 const LocalFrame& frame, UtcNs first_epoch);

}  // namespace gpsemu::sources
