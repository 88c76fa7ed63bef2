#include "emulator/sources/trajectory_source.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <istream>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/sources/pose_message.hpp"

namespace gpsemu::sources {
namespace {

double seconds(std::chrono::nanoseconds d) { return std::chrono::duration<double>(d).count(); }

std::string trim(std::string_view s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string_view::npos) return {};
  const auto b = s.find_last_not_of(" \t\r");
  return std::string(s.substr(a, b - a + 1));
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    out.push_back(trim(std::string_view(line).substr(start, comma == std::string::npos ? std::string::npos
                                                                                       : comma - start)));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

double to_number(const std::string& cell, const std::string& where, const char* column) {
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
  if (cell.empty() || ec != std::errc{} || ptr != cell.data() + cell.size() || !std::isfinite(value)) {
    throw std::runtime_error(fmt::format("{}: column {}: '{}' is not a number", where, column, cell));
  }
  return value;
}

const std::set<std::string>& known_columns() {
  static const std::set<std::string> names{"time_s", "utc",  "lat_deg", "lon_deg", "alt_m",  "east_m", "north_m",
                                           "up_m",   "x_m",  "y_m",     "z_m",     "ve_mps", "vn_mps", "vu_mps",
                                           "yaw_deg", "pitch_deg", "roll_deg"};
  return names;
}

/// Column indices of the header, with the x/y/z aliases folded onto east/north/up.
struct Columns {
  std::map<std::string, std::size_t> index;
  std::size_t count = 0;
  bool absolute_time = false;
  bool geodetic = false;
  bool velocity = false;

  [[nodiscard]] bool has(const char* name) const { return index.count(name) != 0; }
};

Columns read_header(const std::vector<std::string>& cells, const std::string& where) {
  Columns c;
  c.count = cells.size();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    std::string name = cells[i];
    if (!known_columns().count(name)) {
      throw std::runtime_error(fmt::format(
          "{}: unknown column '{}' (accepted: time_s or utc; lat_deg,lon_deg[,alt_m] or east_m,north_m[,up_m] "
          "(x_m,y_m,z_m); optional ve_mps,vn_mps[,vu_mps], yaw_deg, pitch_deg, roll_deg)", where, name));
    }
    if (name == "x_m") name = "east_m";
    if (name == "y_m") name = "north_m";
    if (name == "z_m") name = "up_m";
    if (!c.index.emplace(name, i).second) {
      throw std::runtime_error(fmt::format("{}: column '{}' appears twice", where, cells[i]));
    }
  }
  if (c.has("time_s") == c.has("utc")) {
    throw std::runtime_error(fmt::format("{}: the header must name exactly one time column: time_s (seconds from "
                                         "the first epoch) or utc (ISO 8601)", where));
  }
  c.absolute_time = c.has("utc");
  const bool local = c.has("east_m") || c.has("north_m") || c.has("up_m");
  c.geodetic = c.has("lat_deg") || c.has("lon_deg") || c.has("alt_m");
  if (local == c.geodetic || (local && !(c.has("east_m") && c.has("north_m"))) ||
      (c.geodetic && !(c.has("lat_deg") && c.has("lon_deg")))) {
    throw std::runtime_error(fmt::format("{}: the header must name lat_deg,lon_deg[,alt_m] or east_m,north_m[,up_m]",
                                         where));
  }
  c.velocity = c.has("ve_mps") || c.has("vn_mps") || c.has("vu_mps");
  if (c.velocity && !(c.has("ve_mps") && c.has("vn_mps"))) {
    throw std::runtime_error(fmt::format("{}: velocity needs both ve_mps and vn_mps (vu_mps optional)", where));
  }
  return c;
}

}  // namespace

Trajectory read_trajectory_csv(const std::filesystem::path& path, const LocalFrame& frame, UtcNs first_epoch) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("cannot open trajectory file '{}'", path.string()));
  return read_trajectory_csv(in, path.string(), frame, first_epoch);
}

Trajectory read_trajectory_csv(std::istream& in, const std::string& name, const LocalFrame& frame,
                               UtcNs first_epoch) {
  Trajectory trajectory;
  trajectory.path = name;
  std::optional<Columns> columns;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where = fmt::format("{}:{}", name, line_no);
    const std::string content = trim(line);
    if (content.empty() || content[0] == '#') continue;
    const auto cells = split_csv(content);
    if (!columns) {
      columns = read_header(cells, where);
      trajectory.absolute_time = columns->absolute_time;
      continue;
    }
    if (cells.size() != columns->count) {
      throw std::runtime_error(
          fmt::format("{}: {} values where the header names {}", where, cells.size(), columns->count));
    }
    auto cell = [&](const char* column) -> std::optional<double> {
      const auto it = columns->index.find(column);
      if (it == columns->index.end()) return std::nullopt;
      return to_number(cells[it->second], where, column);
    };
    // A value within +-limit (local metres, metres per second), as for socket poses.
    auto limited = [&](const char* column, double limit, const char* unit) -> std::optional<double> {
      const auto value = cell(column);
      if (value && std::abs(*value) > limit) {
        throw std::runtime_error(fmt::format("{}: column {}: {} is outside +-{:g} {}", where, column, *value, limit, unit));
      }
      return value;
    };
    TrajectoryPoint p;
    if (columns->absolute_time) {
      const std::string& text = cells[columns->index.at("utc")];
      try {
        p.time = parse_iso8601_utc(text);
      } catch (const std::exception& e) {
        throw std::runtime_error(fmt::format("{}: column utc: {}", where, e.what()));
      }
    } else {
      const double t = *cell("time_s");
      if (std::abs(t) > 1e9) throw std::runtime_error(fmt::format("{}: time_s {} is out of range (|t| <= 1e9 s)", where, t));
      p.time = first_epoch + std::chrono::nanoseconds{std::llround(t * 1e9)};
    }
    if (columns->geodetic) {
      const double lat = *cell("lat_deg"), lon = *cell("lon_deg");
      if (lat < -90.0 || lat > 90.0) throw std::runtime_error(fmt::format("{}: latitude {} outside [-90, 90]", where, lat));
      if (lon < -180.0 || lon > 180.0) throw std::runtime_error(fmt::format("{}: longitude {} outside [-180, 180]", where, lon));
      const double alt = cell("alt_m").value_or(frame.origin().alt_m);
      if (alt < kMinAltM || alt > kMaxAltM) {
        throw std::runtime_error(fmt::format("{}: column alt_m: {} is outside [{:g}, {:g}] metres", where, alt,
                                             kMinAltM, kMaxAltM));
      }
      p.position_m = frame.to_enu({lat, lon, alt});
    } else {
      p.position_m = {*limited("east_m", kMaxLocalCoordinateM, "metres"),
                      *limited("north_m", kMaxLocalCoordinateM, "metres"),
                      limited("up_m", kMaxLocalCoordinateM, "metres").value_or(0.0)};
    }
    if (columns->velocity) {
      p.velocity_mps = Enu{*limited("ve_mps", kMaxSpeedMps, "m/s"), *limited("vn_mps", kMaxSpeedMps, "m/s"),
                           limited("vu_mps", kMaxSpeedMps, "m/s").value_or(0.0)};
    }
    if (const auto yaw = limited("yaw_deg", 360.0, "degrees")) p.yaw_deg = wrap_360_deg(*yaw);
    p.tilt = {limited("pitch_deg", 90.0, "degrees").value_or(0.0), limited("roll_deg", 180.0, "degrees").value_or(0.0)};
    if (!trajectory.points.empty() && p.time <= trajectory.points.back().time) {
      throw std::runtime_error(fmt::format("{}: time {} is not after the previous row's: times must increase",
                                           where, cells[columns->index.at(columns->absolute_time ? "utc" : "time_s")]));
    }
    trajectory.points.push_back(p);
  }
  if (!columns) throw std::runtime_error(fmt::format("trajectory file '{}' is empty (no header)", name));
  if (trajectory.points.size() < 2) {
    throw std::runtime_error(fmt::format("trajectory file '{}' has {} rows: at least 2 are needed", name,
                                         trajectory.points.size()));
  }
  return trajectory;
}

TrajectorySource::TrajectorySource(Trajectory trajectory) : trajectory_(std::move(trajectory)) {
  if (trajectory_.points.size() < 2) throw std::invalid_argument("a trajectory needs at least two points");
}

std::optional<Truth> TrajectorySource::truth_at(UtcNs t) {
  const auto& pts = trajectory_.points;
  if (t < pts.front().time || t > pts.back().time) return std::nullopt;
  // The segment [i, i + 1] holding t (the last segment for the last point).
  auto it = std::upper_bound(pts.begin(), pts.end(), t, [](UtcNs x, const TrajectoryPoint& p) { return x < p.time; });
  std::size_t i = static_cast<std::size_t>(it - pts.begin()) - 1;
  if (i + 1 >= pts.size()) i = pts.size() - 2;
  const TrajectoryPoint& a = pts[i];
  const TrajectoryPoint& b = pts[i + 1];
  const double span_s = seconds(b.time - a.time);
  const double f = seconds(t - a.time) / span_s;
  const Enu position = a.position_m + f * (b.position_m - a.position_m);
  const Enu velocity = (a.velocity_mps && b.velocity_mps)
                           ? *a.velocity_mps + f * (*b.velocity_mps - *a.velocity_mps)
                           : (1.0 / span_s) * (b.position_m - a.position_m);
  return Truth{position, velocity, interpolate_yaw_deg(a.yaw_deg, b.yaw_deg, f), lerp_tilt(a.tilt, b.tilt, f)};
}

std::string TrajectorySource::describe() const {
  const auto& pts = trajectory_.points;
  return fmt::format("replay:{} ({} rows over {:.3f} s, {}; velocity {})", trajectory_.path, pts.size(),
                     seconds(pts.back().time - pts.front().time),
                     trajectory_.absolute_time
                         ? fmt::format("utc {} to {}", format_iso8601_utc(pts.front().time),
                                       format_iso8601_utc(pts.back().time))
                         : "time_s from the first epoch",
                     pts.front().velocity_mps ? "from the file" : "from the track");
}

std::unique_ptr<PoseSource> make_trajectory_source(const std::filesystem::path& path, const LocalFrame& frame,
                                                   UtcNs first_epoch) {
  Trajectory trajectory = read_trajectory_csv(path, frame, first_epoch);
  if (trajectory.points.back().time < first_epoch) {
    throw std::runtime_error(fmt::format(
        "trajectory file '{}' ends at {}, before the first epoch {}: give --start-time within the trajectory",
        path.string(), format_iso8601_utc(trajectory.points.back().time), format_iso8601_utc(first_epoch)));
  }
  return std::make_unique<TrajectorySource>(std::move(trajectory));
}

}  // namespace gpsemu::sources
