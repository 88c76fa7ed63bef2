#include "emulator/model/sky/dop.hpp"

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
  // Columns: east, north, up, then one per clock group present, in group order.
  std::array<int, kMaxClocks> column{-1, -1, -1, -1};
  for (const UsedSatellite& s : used) column[static_cast<std::size_t>(clock_group(s.system))] = 0;
  int n = 3;
  for (int& c : column) {
    if (c == 0) c = n++;
  }
  if (static_cast<int>(used.size()) < n) return {};
  // Normal matrix N = G^T G, then invert (Gauss-Jordan with partial pivoting).
  double a[kMaxUnknowns][2 * kMaxUnknowns] = {};
  constexpr double deg = std::numbers::pi / 180.0;
  for (const UsedSatellite& s : used) {
    const double ce = std::cos(s.elevation_deg * deg);
    double row[kMaxUnknowns] = {};
    row[0] = -ce * std::sin(s.azimuth_deg * deg);
    row[1] = -ce * std::cos(s.azimuth_deg * deg);
    row[2] = -std::sin(s.elevation_deg * deg);
    row[column[static_cast<std::size_t>(clock_group(s.system))]] = 1.0;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) a[i][j] += row[i] * row[j];
    }
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
