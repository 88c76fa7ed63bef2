// The embedded RINEX file's real GPS records, computed by hand (IS-GPS-200, sky_kepler.hpp) and
// seen from Madison through GeographicLib, against the azimuth and elevation the sky writes; and
// the sky's interpolation between its orbit nodes against RTKLIB's own positions.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "emulator/model/sky.hpp"
#include "emulator/model/sky/embedded_data.hpp"
#include "emulator/model/sky/orbits.hpp"
#include "emulator/model/sky/profile.hpp"
#include "tests/unit/model/sky_kepler.hpp"

namespace gpsemu {
namespace {

using namespace sky_test_support;

// --- A real record of the embedded RINEX file, by hand, against what the sky writes ------------

/// The RINEX 3 GPS records of the embedded navigation file (IS-GPS-200 parameters, toe in GPS
/// seconds since 1980).
std::vector<std::pair<int, Kepler>> embedded_gps_records() {
  std::vector<std::pair<int, Kepler>> out;
  std::istringstream in{std::string(sky::embedded_rinex_nav_text())};
  std::string line;
  bool body = false;
  const auto field = [](const std::string& l, int index) {
    std::string text = l.substr(static_cast<std::size_t>(4 + 19 * index), 19);
    for (char& c : text) {
      if (c == 'D') c = 'E';
    }
    return std::stod(text);
  };
  while (std::getline(in, line)) {
    if (!body) {
      body = line.find("END OF HEADER") != std::string::npos;
      continue;
    }
    if (line.empty() || line[0] != 'G') continue;
    std::array<std::string, 7> l;
    for (auto& x : l) std::getline(in, x);
    Kepler k;
    k.af0 = std::stod(line.substr(23, 19));
    k.iode = field(l[0], 0), k.crs = field(l[0], 1), k.dn = field(l[0], 2), k.m0 = field(l[0], 3);
    k.cuc = field(l[1], 0), k.e = field(l[1], 1), k.cus = field(l[1], 2), k.sqrt_a = field(l[1], 3);
    k.toe = field(l[2], 0), k.cic = field(l[2], 1), k.omega0 = field(l[2], 2), k.cis = field(l[2], 3);
    k.i0 = field(l[3], 0), k.crc = field(l[3], 1), k.w = field(l[3], 2), k.omega_dot = field(l[3], 3);
    k.idot = field(l[4], 0), k.week = field(l[4], 2);
    if (field(l[5], 1) != 0.0) continue;  // unhealthy: the sky leaves it out
    out.emplace_back(std::stoi(line.substr(1, 2)), k);
  }
  return out;
}

// The whole chain (RTKLIB reading the real file, the nodes and their interpolation, the line of
// sight, the rounding) against IS-GPS-200 by hand from the same record and GeographicLib: each GPS
// satellite above 5 degrees at Madison ten minutes after its record's toe is listed where the
// hand computation sees it, within the half degree of NMEA's integer degrees (+0.05).
TEST(SkyOrbits, SkyAzimuthElevationMatchesAHandComputationOfTheRealRecords) {
  SkyOptions o;
  o.profile = sky::profile_of(ubx::ReceiverModel::ublox_m8n);
  int checked = 0;
  for (const auto& [prn, k] : embedded_gps_records()) {
    const double toe_gps_s = k.week * 604800.0 + k.toe;
    const double t_gps_s = toe_gps_s + 600.0;
    if (t_gps_s < gps_seconds_of(parse_iso8601_utc("2018-07-29T00:00:00Z")) ||
        t_gps_s >= gps_seconds_of(parse_iso8601_utc("2018-07-30T00:00:00Z"))) {
      continue;  // the sky maps times outside the file's day; keep to its own day
    }
    const sky::Ecef hand = is_gps_200(k, 600.0);
    const sky::AzEl expected = azel_by_geographiclib(kMadison, hand);
    if (expected.elevation_deg < 5.0) continue;
    Sky sky(o, kMadison);
    nmea::Fix fix;
    const UtcNs when{std::chrono::seconds(static_cast<std::int64_t>(t_gps_s) + 315964800 - 18)};
    (void)sky.fill(when, {}, fix);
    const nmea::SatelliteInView* listed = nullptr;
    for (int i = 0; i < fix.satellites_in_view; ++i) {
      const auto& s = fix.satellites[static_cast<std::size_t>(i)];
      if (s.system == nmea::GnssSystem::gps && s.sv_id == prn) listed = &s;
    }
    ASSERT_NE(listed, nullptr) << "G" << prn << " at elevation " << expected.elevation_deg;
    EXPECT_LE(std::fabs(listed->elevation_deg - expected.elevation_deg), 0.55) << "G" << prn;
    if (expected.elevation_deg < 85.0) {
      const double daz = std::fabs(listed->azimuth_deg - expected.azimuth_deg);
      EXPECT_LE(std::min(daz, 360.0 - daz), 0.55) << "G" << prn;
    }
    ++checked;
  }
  EXPECT_GE(checked, 10);
}

// Positions between the nodes (ten minutes apart, cubic Hermite) against RTKLIB's own at every
// minute: within 50 m (0.0002 degree seen from the ground).
TEST(SkyOrbits, InterpolatedPositionsStayCloseToRtklibs) {
  const auto orbits = sky::Orbits::embedded_default();
  const double start = orbits->coverage_start() + 6 * 3600.0;
  constexpr double node_s = 600.0;
  int checked = 0;
  for (std::size_t i = 0; i < orbits->satellites().size(); ++i) {
    const auto a = orbits->motion(i, start), b = orbits->motion(i, start + node_s);
    if (!a || !b) continue;
    for (double x = 0.1; x < 1.0; x += 0.2) {
      const auto exact = orbits->position(i, start + x * node_s);
      if (!exact) continue;
      const double x2 = x * x, x3 = x2 * x;
      const double h00 = 2 * x3 - 3 * x2 + 1, h10 = (x3 - 2 * x2 + x) * node_s, h01 = -2 * x3 + 3 * x2, h11 = (x3 - x2) * node_s;
      const sky::Ecef p{h00 * a->position.x_m + h10 * a->vx_mps + h01 * b->position.x_m + h11 * b->vx_mps,
                        h00 * a->position.y_m + h10 * a->vy_mps + h01 * b->position.y_m + h11 * b->vy_mps,
                        h00 * a->position.z_m + h10 * a->vz_mps + h01 * b->position.z_m + h11 * b->vz_mps};
      EXPECT_LT(distance_m(p, *exact), 50.0) << static_cast<int>(orbits->satellites()[i].system) << " "
                                             << orbits->satellites()[i].sv_id << " x " << x;
      ++checked;
    }
  }
  EXPECT_GE(checked, 200);
}
}  // namespace
}  // namespace gpsemu
