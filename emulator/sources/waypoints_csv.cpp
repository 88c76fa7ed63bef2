// Waypoint CSV reader for sim:waypoints:FILE. A header names the columns: either
// east_m,north_m[,up_m][,speed_mps] (metres about the origin) or lat_deg,lon_deg[,alt_m][,speed_mps]
// (alt_m above MSL). '#' starts a comment line; blank lines are ignored.
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <istream>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/sources/pose_message.hpp"
#include "emulator/sources/sim.hpp"

namespace gpsemu::sources {
namespace {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  for (const char c : line) {
    if (c == ',') {
      out.push_back(cell);
      cell.clear();
    } else if (c != ' ' && c != '\t' && c != '\r') {
      cell += c;
    }
  }
  out.push_back(cell);
  return out;
}

double to_number(const std::string& cell, const std::string& where) {
  double value = 0.0;
  auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
  if (cell.empty() || ec != std::errc{} || ptr != cell.data() + cell.size() || !std::isfinite(value)) {
    throw std::runtime_error(fmt::format("{}: '{}' is not a number", where, cell));
  }
  return value;
}

}  // namespace

std::vector<Waypoint> read_waypoints(const std::filesystem::path& path, const LocalFrame& frame,
                                     double default_speed_mps) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("cannot open waypoint file '{}'", path.string()));
  return read_waypoints(in, path.string(), frame, default_speed_mps);
}

std::vector<Waypoint> read_waypoints(std::istream& in, const std::string& name, const LocalFrame& frame,
                                     double default_speed_mps) {
  std::map<std::string, std::size_t> column;
  std::vector<Waypoint> points;
  std::string line;
  int line_no = 0;
  bool geodetic = false;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where = fmt::format("{}:{}", name, line_no);
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto cells = split_csv(line);
    if (column.empty()) {
      for (std::size_t i = 0; i < cells.size(); ++i) {
        if (!column.emplace(cells[i], i).second) {
          throw std::runtime_error(fmt::format("{}: column '{}' appears twice in the header", where, cells[i]));
        }
      }
      const bool local = column.count("east_m") && column.count("north_m");
      geodetic = column.count("lat_deg") && column.count("lon_deg");
      if (local == geodetic) {
        throw std::runtime_error(fmt::format(
            "{}: the header must name east_m,north_m or lat_deg,lon_deg (optional up_m/alt_m, speed_mps)",
            where));
      }
      continue;
    }
    if (cells.size() != column.size()) {
      throw std::runtime_error(
          fmt::format("{}: {} values where the header names {}", where, cells.size(), column.size()));
    }
    auto cell = [&](const char* column_name) -> std::optional<double> {
      const auto it = column.find(column_name);
      if (it == column.end() || cells[it->second].empty()) return std::nullopt;
      return to_number(cells[it->second], fmt::format("{} column {}", where, column_name));
    };
    auto required = [&](const char* column_name) {
      const auto value = cell(column_name);
      if (!value) throw std::runtime_error(fmt::format("{}: column {} is empty", where, column_name));
      return *value;
    };
    auto local_m = [&](const char* column_name, double value) {
      if (std::abs(value) > kMaxLocalCoordinateM) {
        throw std::runtime_error(fmt::format("{}: {} {} is outside +-{:g} metres", where, column_name, value,
                                             kMaxLocalCoordinateM));
      }
      return value;
    };
    Waypoint w;
    if (geodetic) {
      const double lat = required("lat_deg"), lon = required("lon_deg");
      if (lat < -90.0 || lat > 90.0) throw std::runtime_error(fmt::format("{}: latitude {} outside [-90, 90]", where, lat));
      if (lon < -180.0 || lon > 180.0) throw std::runtime_error(fmt::format("{}: longitude {} outside [-180, 180]", where, lon));
      const double alt = cell("alt_m").value_or(frame.origin().alt_m);
      if (alt < kMinAltM || alt > kMaxAltM) {
        throw std::runtime_error(fmt::format("{}: alt_m {} outside [{:g}, {:g}] metres", where, alt, kMinAltM, kMaxAltM));
      }
      w.position_m = frame.to_enu({lat, lon, alt});
    } else {
      w.position_m = {local_m("east_m", required("east_m")), local_m("north_m", required("north_m")),
                      local_m("up_m", cell("up_m").value_or(0.0))};
    }
    w.speed_mps = cell("speed_mps").value_or(default_speed_mps);
    if (!(w.speed_mps > 0.0) || w.speed_mps > kMaxSpeedMps) {
      throw std::runtime_error(fmt::format("{}: speed_mps must be > 0 and <= {:g}", where, kMaxSpeedMps));
    }
    points.push_back(w);
  }
  if (points.empty()) throw std::runtime_error(fmt::format("waypoint file '{}' has no waypoints", name));
  return points;
}

}  // namespace gpsemu::sources
