#include "emulator/faults/area.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::faults {
namespace {

constexpr double kMeanEarthRadiusM = 6371008.8;
constexpr double kDegToRad = M_PI / 180.0;

double number(std::string_view text, std::string_view what) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  double x = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(x))
    throw std::invalid_argument(fmt::format("where: {}: '{}' is not a number", what, text));
  return x;
}

std::vector<std::string_view> split(std::string_view text, char sep) {
  std::vector<std::string_view> out;
  while (true) {
    const std::size_t at = text.find(sep);
    out.push_back(text.substr(0, at));
    if (at == std::string_view::npos) break;
    text.remove_prefix(at + 1);
  }
  return out;
}

Geodetic lat_lon(std::string_view a, std::string_view b) {
  const double lat = number(a, "latitude");
  const double lon = number(b, "longitude");
  if (lat < -90.0 || lat > 90.0) throw std::invalid_argument(fmt::format("where: latitude {} is outside [-90, 90]", lat));
  if (lon < -180.0 || lon > 180.0) throw std::invalid_argument(fmt::format("where: longitude {} is outside [-180, 180]", lon));
  return {lat, lon, 0.0};
}

}  // namespace

double surface_distance_m(const Geodetic& a, const Geodetic& b) {
  const double p1 = a.lat_deg * kDegToRad, p2 = b.lat_deg * kDegToRad;
  const double dp = p2 - p1, dl = (b.lon_deg - a.lon_deg) * kDegToRad;
  const double h = std::sin(dp / 2) * std::sin(dp / 2) + std::cos(p1) * std::cos(p2) * std::sin(dl / 2) * std::sin(dl / 2);
  return 2.0 * kMeanEarthRadiusM * std::asin(std::min(1.0, std::sqrt(h)));
}

bool Area::contains(const Geodetic& p) const {
  if (shape == Shape::circle) return surface_distance_m(points.front(), p) <= radius_m;
  // Ray casting in (longitude, latitude): fine for areas far smaller than a hemisphere.
  bool inside = false;
  for (std::size_t i = 0, j = points.size() - 1; i < points.size(); j = i++) {
    const Geodetic& a = points[i];
    const Geodetic& b = points[j];
    if ((a.lat_deg > p.lat_deg) != (b.lat_deg > p.lat_deg)) {
      const double lon_at = a.lon_deg + (p.lat_deg - a.lat_deg) / (b.lat_deg - a.lat_deg) * (b.lon_deg - a.lon_deg);
      if (p.lon_deg < lon_at) inside = !inside;
    }
  }
  return inside;
}

std::string Area::text() const {
  if (shape == Shape::circle) return fmt::format("circle:{},{},{}", points.front().lat_deg, points.front().lon_deg, radius_m);
  std::string s = "polygon:";
  for (std::size_t i = 0; i < points.size(); ++i) s += fmt::format("{}{},{}", i ? ";" : "", points[i].lat_deg, points[i].lon_deg);
  return s;
}

Area parse_area(std::string_view text) {
  Area area;
  if (text.rfind("circle:", 0) == 0) {
    const auto parts = split(text.substr(7), ',');
    if (parts.size() != 3)
      throw std::invalid_argument(fmt::format("where: expected circle:LAT,LON,RADIUS_M, got '{}'", text));
    area.points.push_back(lat_lon(parts[0], parts[1]));
    area.radius_m = number(parts[2], "radius");
    if (!(area.radius_m > 0.0) || area.radius_m > 2e7)
      throw std::invalid_argument(fmt::format("where: radius {} m is outside (0, 2e7]", area.radius_m));
    return area;
  }
  if (text.rfind("polygon:", 0) == 0) {
    area.shape = Area::Shape::polygon;
    for (const std::string_view corner : split(text.substr(8), ';')) {
      const auto ll = split(corner, ',');
      if (ll.size() != 2)
        throw std::invalid_argument(fmt::format("where: a polygon corner is LAT,LON, got '{}'", corner));
      area.points.push_back(lat_lon(ll[0], ll[1]));
    }
    if (area.points.size() < 3)
      throw std::invalid_argument(fmt::format("where: a polygon needs at least 3 corners, got {}", area.points.size()));
    return area;
  }
  throw std::invalid_argument(
      fmt::format("where: expected circle:LAT,LON,RADIUS_M or polygon:LAT,LON;LAT,LON;LAT,LON, got '{}'", text));
}

}  // namespace gpsemu::faults
