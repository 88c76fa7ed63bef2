#include "emulator/model/sky/dop.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace gpsemu::sky {
namespace {

constexpr int kMaxClocks = 4;  // GPS(+QZSS+SBAS), GLONASS, Galileo, BeiDou
constexpr int kMaxUnknowns = 3 + kMaxClocks;

int clock_group(nmea::GnssSystem s) {
  switch (s) {
    case nmea::GnssSystem::glonass: return 1;
    case nmea::GnssSystem::galileo: return 2;
    case nmea::GnssSystem::beidou: return 3;
    default: return 0;  // GPS, QZSS, SBAS: GPS time
  }
}

}  // namespace

Dops multi_clock_dops(std::span<const UsedSatellite> used) {
  std::array<LineOfSight, 256> lines{};
  const std::size_t n = std::min(used.size(), lines.size());
  constexpr double deg = std::numbers::pi / 180.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double ce = std::cos(used[i].elevation_deg * deg);
    lines[i] = {ce * std::sin(used[i].azimuth_deg * deg), ce * std::cos(used[i].azimuth_deg * deg),
                std::sin(used[i].elevation_deg * deg), used[i].system};
  }
  return multi_clock_dops(std::span<const LineOfSight>(lines.data(), n));
}

Dops multi_clock_dops(std::span<const LineOfSight> used) {
  // Columns: east, north, up, then one per clock group present, in group order.
  std::array<int, kMaxClocks> column{-1, -1, -1, -1};
  for (const LineOfSight& s : used) column[static_cast<std::size_t>(clock_group(s.system))] = 0;
  int n = 3;
  for (int& c : column) {
    if (c == 0) c = n++;
  }
  if (static_cast<int>(used.size()) < n) return {};
  // Normal matrix N = G^T G, then invert (Gauss-Jordan with partial pivoting).
  double a[kMaxUnknowns][2 * kMaxUnknowns] = {};
  // Each row is [-east, -north, -up, 1 in the satellite's clock column]: only the position block,
  // the satellite's clock column and its diagonal gain terms (the same sums as the full product).
  for (const LineOfSight& s : used) {
    const double v[3] = {-s.east, -s.north, -s.up};
    const int c = column[static_cast<std::size_t>(clock_group(s.system))];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j <= i; ++j) a[i][j] += v[i] * v[j];
      a[i][c] += v[i];
    }
    a[c][c] += 1.0;
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < i; ++j) a[j][i] = a[i][j];
    for (int c = 3; c < n; ++c) a[c][i] = a[i][c];
  }
  for (int i = 0; i < n; ++i) a[i][n + i] = 1.0;
  for (int c = 0; c < n; ++c) {
    int pivot = c;
    for (int r = c + 1; r < n; ++r) {
      if (std::fabs(a[r][c]) > std::fabs(a[pivot][c])) pivot = r;
    }
    if (std::fabs(a[pivot][c]) < 1e-12) return {};
    if (pivot != c) {
      for (int j = 0; j < 2 * n; ++j) std::swap(a[c][j], a[pivot][j]);
    }
    const double inv = 1.0 / a[c][c];
    for (int j = 0; j < 2 * n; ++j) a[c][j] *= inv;
    for (int r = 0; r < n; ++r) {
      if (r == c || a[r][c] == 0.0) continue;
      const double f = a[r][c];
      for (int j = 0; j < 2 * n; ++j) a[r][j] -= f * a[c][j];
    }
  }
  const auto q = [&](int i) { return a[i][n + i]; };
  Dops d;
  d.hdop = std::sqrt(q(0) + q(1));
  d.vdop = std::sqrt(q(2));
  d.pdop = std::sqrt(q(0) + q(1) + q(2));
  d.tdop = std::sqrt(q(3));
  double trace = 0.0;
  for (int i = 0; i < n; ++i) trace += q(i);
  d.gdop = std::sqrt(trace);
  return d;
}

}  // namespace gpsemu::sky
