// The embedded RINEX file's real GPS records, computed by hand (IS-GPS-200, sky_kepler.hpp) and
// seen from Madison through GeographicLib, against the azimuth and elevation the sky writes; and
// the sky's interpolation between its orbit nodes against RTKLIB's own positions.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <fstream>
#include <filesystem>
#include <cstdio>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include "emulator/model/sky.hpp"
#include "emulator/model/sky/embedded_data.hpp"
#include "emulator/model/sky/orbits.hpp"
#include "emulator/model/receiver_models.hpp"
#include "tests/support/scratch.hpp"
#include "tests/unit/model/sky_kepler.hpp"

namespace gpsemu {
namespace {
namespace sky_records_test {

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
  o.tracking = facts_of(ReceiverModel::ublox_m8n).tracking;
  int checked = 0;
  for (const auto& [prn, k] : embedded_gps_records()) {
    const double toe_gps_s = k.week * 604800.0 + k.toe;
    const double t_gps_s = toe_gps_s + 600.0;
    if (t_gps_s < gps_seconds_of(parse_iso8601_utc("2026-03-09T00:00:00Z")) ||
        t_gps_s >= gps_seconds_of(parse_iso8601_utc("2026-03-10T00:00:00Z"))) {
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

/// Whether satellite `i`'s orbit jumps (by more than 10 m beyond its motion) within [t0, t1]:
/// the sky switched from one record to another there.
bool switches_record(const sky::Orbits& orbits, std::size_t i, double t0, double t1) {
  // Over 1 s the velocity predicts any orbit to within a metre (0.6 m/s² of gravity at most).
  auto previous = orbits.motion(i, t0);
  for (double t = t0 + 1.0; previous && t <= t1; t += 1.0) {
    const auto now = orbits.motion(i, t);
    if (!now) return true;
    const sky::Ecef expected{previous->position.x_m + previous->vx_mps, previous->position.y_m + previous->vy_mps,
                             previous->position.z_m + previous->vz_mps};
    if (distance_m(expected, now->position) > 10.0) return true;
    previous = now;
  }
  return false;
}

// Positions between the nodes (ten minutes apart, cubic Hermite) against RTKLIB's own at every
// minute: within 50 m (0.0002 degree seen from the ground), except across the moment the sky
// switches from one record of a satellite to the next (a jump of the two records' difference
// near the ends of their validity, or of an extrapolation's error, below). At 07:05, between the
// moments the thinned file hands most satellites over to their next record (GPS every 4 h from
// 02:00, BeiDou at 06:00 and 18:00, GLONASS on the hour and half hour).
TEST(SkyOrbits, InterpolatedPositionsStayCloseToRtklibs) {
  const auto orbits = sky::Orbits::embedded_default();
  const double start = orbits->coverage_start() + 7 * 3600.0 + 300.0;
  constexpr double node_s = 600.0;
  int checked = 0, switched = 0;
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
      if (distance_m(p, *exact) >= 50.0 && switches_record(*orbits, i, start, start + node_s)) {
        ++switched;  // an extrapolated record gives way to a valid one inside the interval
        break;
      }
      EXPECT_LT(distance_m(p, *exact), 50.0) << static_cast<int>(orbits->satellites()[i].system) << " "
                                             << orbits->satellites()[i].sv_id << " x " << x;
      ++checked;
    }
  }
  std::printf("%d positions checked, %d satellites switch records in the interval\n", checked, switched);
  EXPECT_GE(checked, 200);
  EXPECT_LE(switched, 10);
}

// The file holds a satellite's records only for the hours they were broadcast and merged (the
// embedded file covers the whole day, data/sky/README.md; a file given with --ephemeris may
// not); at other moments the nearest record is extrapolated. Every satellite of the file then
// has a position all day, except while the record in force marks it unhealthy (the sky leaves
// it out, as a receiver does), and where the
// sky switches from an extrapolated record to a valid one the orbit does not jump by more than
// the extrapolation's error (docs/sky.md; 10 km is 0.03 degree seen from the ground). Each
// 5-minute step is checked against the trapezoid of its two ends' velocities (within ~0.2 km on
// an orbit).
TEST(SkyOrbits, EverySatelliteOfTheFileHasAPositionAllDayWithoutAJumpAtItsRecords) {
  const auto orbits = sky::Orbits::embedded_default();
  const double start = orbits->coverage_start();
  constexpr double step_s = 300.0;
  int satellites = 0, all_day = 0, unhealthy_most_of_the_day = 0;
  for (std::size_t i = 0; i < orbits->satellites().size(); ++i) {
    const auto system = orbits->satellites()[i].system;
    const int sv = orbits->satellites()[i].sv_id;
    // SBAS and some QZSS come from two-line elements: their own test is above.
    if (system == nmea::GnssSystem::qzss || system == nmea::GnssSystem::sbas) continue;
    ++satellites;
    double worst_m = 0.0;
    int missing = 0;
    auto previous = orbits->motion(i, start);
    for (double t = start + step_s; t < start + 86400.0; t += step_s) {
      const auto now = orbits->motion(i, t);
      if (!now) ++missing;
      if (previous && now) {
        const sky::Ecef expected{previous->position.x_m + 0.5 * step_s * (previous->vx_mps + now->vx_mps),
                                 previous->position.y_m + 0.5 * step_s * (previous->vy_mps + now->vy_mps),
                                 previous->position.z_m + 0.5 * step_s * (previous->vz_mps + now->vz_mps)};
        worst_m = std::max(worst_m, distance_m(expected, now->position));
      }
      previous = now;
    }
    // Left out only while a record in force says unhealthy: at most a few hours of the day, but
    // for the few satellites whose records say so most of the day (G20, R17, R20 on 2026-03-09).
    if (missing * step_s > 6 * 3600.0) {
      ++unhealthy_most_of_the_day;
      std::printf("system %d, %d: left out %.1f h\n", static_cast<int>(system), sv, missing * step_s / 3600.0);
    }
    if (missing == 0) ++all_day;
    EXPECT_LT(worst_m, 10'000.0) << static_cast<int>(system) << " " << sv;
  }
  EXPECT_LE(unhealthy_most_of_the_day, 3);
  EXPECT_GE(satellites, 120);  // GPS 32, GLONASS 24, Galileo 26, BeiDou 43 healthy in the file
  EXPECT_GE(all_day, satellites - 10) << "all but a few satellites are healthy all day";
}
// How far the extrapolation of a record is off: the embedded file cut to its records of epoch up
// to 03:00 of its day (read from a temporary file) against the whole file's orbit then (its own
// later records, which cover the whole day), every satellite in both at 05, 07, 10, 14 and 21
// o'clock (2-21 hours after the cut's last records: a file given with --ephemeris that was
// fetched part-way through its day is extrapolated that far). Measured and written in
// docs/sky.md; the bounds here are 20 km, and 200 km for GLONASS, whose orbit is integrated from
// a state vector (0.05 and 0.5 degree seen from the ground at their distance).
TEST(SkyOrbits, ExtrapolatedRecordsStayWithinKilometresOfTheValidOnes) {
  const std::string text(sky::embedded_rinex_nav_text());
  std::istringstream in(text);
  std::ostringstream early;
  bool body = false, keep = true;
  for (std::string line; std::getline(in, line);) {
    if (body && !line.empty() && line[0] != ' ') keep = line.substr(4, 19) <= "2026 03 09 03 00 00";
    if (!body || keep) early << line << "\n";
    body = body || line.find("END OF HEADER") != std::string::npos;
  }
  const auto path = test::scratch_root() / ("gpsemu_sky_early_" + std::to_string(::getpid()) + ".rnx");
  std::ofstream(path) << early.str();
  const auto cut = sky::Orbits::from_rinex_nav(path.string());
  std::filesystem::remove(path);
  const auto whole = sky::Orbits::embedded_default();
  const double start = whole->coverage_start();
  std::map<std::pair<nmea::GnssSystem, int>, double> worst_m;  // by system and hours
  std::map<nmea::GnssSystem, int> compared;
  for (std::size_t i = 0; i < whole->satellites().size(); ++i) {
    const auto id = whole->satellites()[i];
    const auto j = std::find(cut->satellites().begin(), cut->satellites().end(), id);
    if (j == cut->satellites().end()) continue;
    const auto k = static_cast<std::size_t>(j - cut->satellites().begin());
    for (const int hours : {5, 7, 10, 14, 21}) {
      const double t = start + hours * 3600.0;
      const auto a = whole->position(i, t), b = cut->position(k, t);
      if (!a || !b) continue;
      double& w = worst_m[{id.system, hours}];
      w = std::max(w, distance_m(*a, *b));
      if (hours == 21) ++compared[id.system];
    }
  }
  for (const auto& [key, m] : worst_m) {
    std::printf("system %d, %d h: worst %.1f km\n", static_cast<int>(key.first), key.second, m / 1000.0);
    EXPECT_LT(m, key.first == nmea::GnssSystem::glonass ? 200e3 : 20e3) << static_cast<int>(key.first) << " " << key.second << " h";
  }
  EXPECT_GE(compared[nmea::GnssSystem::gps], 10);
  EXPECT_GE(compared[nmea::GnssSystem::galileo], 10);
  EXPECT_GE(compared[nmea::GnssSystem::beidou], 20);
  EXPECT_GE(compared[nmea::GnssSystem::glonass], 8);
}
}  // namespace sky_records_test
}  // namespace
}  // namespace gpsemu
