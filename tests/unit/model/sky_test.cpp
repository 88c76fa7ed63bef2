// The sky: orbits from RTKLIB checked against independent computations written here (the
// IS-GPS-200 ephemeris algorithm for a RINEX record and for the real records of the embedded file,
// with GeographicLib for azimuth/elevation; Kepler with J2 secular rates and a GMST rotation for
// the embedded two-line elements), the
// multi-clock DOP against RTKLIB's single-clock dops() on one system, and the per-model sky:
// systems, elevation mask, obstruction, channels, C/N0 by elevation.
#include <gtest/gtest.h>

#include <GeographicLib/LocalCartesian.hpp>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <unistd.h>
#include <vector>

#include "emulator/model/sky.hpp"
#include "emulator/model/sky/dop.hpp"
#include "emulator/model/sky/embedded_data.hpp"
#include "emulator/model/sky/orbits.hpp"
#include "emulator/model/sky/profile.hpp"

namespace gpsemu {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kMu = 3.986005e14;          // WGS84 GM of IS-GPS-200 (m^3/s^2)
constexpr double kOmegaE = 7.2921151467e-5;  // earth rotation (rad/s)
const Geodetic kMadison{43.0725, -89.4125, 260.0 - 33.9};  // ellipsoidal height

double distance_m(const sky::Ecef& a, const sky::Ecef& b) {
  return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m, a.z_m - b.z_m);
}

sky::AzEl azel_by_geographiclib(const Geodetic& rx, const sky::Ecef& sat) {
  const GeographicLib::LocalCartesian frame(rx.lat_deg, rx.lon_deg, rx.alt_m);
  double e = 0, n = 0, u = 0;
  // LocalCartesian::Forward takes geodetic; go through the Geocentric inverse.
  double lat = 0, lon = 0, h = 0;
  GeographicLib::Geocentric::WGS84().Reverse(sat.x_m, sat.y_m, sat.z_m, lat, lon, h);
  frame.Forward(lat, lon, h, e, n, u);
  double az = std::atan2(e, n) / kDeg;
  if (az < 0) az += 360.0;
  return {az, std::atan2(u, std::hypot(e, n)) / kDeg};
}

// --- A RINEX 3 GPS record, and IS-GPS-200's algorithm -----------------------------------------

struct Kepler {
  double af0 = 1.0e-5, af1 = 1.0e-12, af2 = 0.0;
  double iode = 42, crs = 35.5, dn = 4.5e-9, m0 = 0.3;
  double cuc = 1.8e-6, e = 0.0105, cus = 8.2e-6, sqrt_a = 5153.65;
  double toe = 180000.0, cic = -1.1e-7, omega0 = 1.0, cis = 9.0e-8;
  double i0 = 0.958, crc = 210.3, w = 0.52, omega_dot = -8.1e-9;
  double idot = 1.2e-10, week = 2134;
};

std::string d19(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%19.12E", v);
  return b;
}

std::string rinex3_gps_nav(const Kepler& k) {
  std::ostringstream o;
  const auto header = [&](const std::string& text, const std::string& label) {
    std::string line = text;
    line.resize(60, ' ');
    o << line << label << "\n";
  };
  header("     3.03           N: GNSS NAV DATA    G: GPS", "RINEX VERSION / TYPE");
  header("", "END OF HEADER");
  // 2020-12-01 02:00:00 GPST = week 2134, 180000 s.
  o << "G07 2020 12 01 02 00 00" << d19(k.af0) << d19(k.af1) << d19(k.af2) << "\n";
  const auto line = [&](double a, double b, double c, double d) { o << "    " << d19(a) << d19(b) << d19(c) << d19(d) << "\n"; };
  line(k.iode, k.crs, k.dn, k.m0);
  line(k.cuc, k.e, k.cus, k.sqrt_a);
  line(k.toe, k.cic, k.omega0, k.cis);
  line(k.i0, k.crc, k.w, k.omega_dot);
  line(k.idot, 1.0, k.week, 0.0);
  line(2.0, 0.0, 5.0e-9, k.iode);
  line(172800.0, 4.0, 0.0, 0.0);
  return o.str();
}

sky::Ecef is_gps_200(const Kepler& k, double tk) {
  const double a = k.sqrt_a * k.sqrt_a;
  const double n = std::sqrt(kMu / (a * a * a)) + k.dn;
  const double m = k.m0 + n * tk;
  double ecc_anomaly = m;
  for (int i = 0; i < 30; ++i) ecc_anomaly = m + k.e * std::sin(ecc_anomaly);
  const double nu = std::atan2(std::sqrt(1 - k.e * k.e) * std::sin(ecc_anomaly), std::cos(ecc_anomaly) - k.e);
  const double phi = nu + k.w;
  const double s2 = std::sin(2 * phi), c2 = std::cos(2 * phi);
  const double u = phi + k.cus * s2 + k.cuc * c2;
  const double r = a * (1 - k.e * std::cos(ecc_anomaly)) + k.crs * s2 + k.crc * c2;
  const double inc = k.i0 + k.cis * s2 + k.cic * c2 + k.idot * tk;
  const double omega = k.omega0 + (k.omega_dot - kOmegaE) * tk - kOmegaE * k.toe;
  const double xp = r * std::cos(u), yp = r * std::sin(u);
  return {xp * std::cos(omega) - yp * std::cos(inc) * std::sin(omega), xp * std::sin(omega) + yp * std::cos(inc) * std::cos(omega),
          yp * std::sin(inc)};
}

TEST(SkyOrbits, RinexRecordGivesTheIsGps200PositionOfItsEphemeris) {
  const Kepler k;
  const auto path = std::filesystem::temp_directory_path() / ("gpsemu_sky_" + std::to_string(::getpid()) + ".rnx");
  std::ofstream(path) << rinex3_gps_nav(k);
  const auto orbits = sky::Orbits::from_rinex_nav(path.string());
  std::filesystem::remove(path);
  ASSERT_EQ(orbits->satellites().size(), 1u);
  EXPECT_EQ(orbits->satellites()[0], (sky::SatelliteId{nmea::GnssSystem::gps, 7}));
  const double toe_gps_s = 2134 * 604800.0 + k.toe;
  EXPECT_EQ(orbits->coverage_start(), 2134 * 604800.0 + 2 * 86400.0) << "the record's day";
  for (const double tk : {0.0, 1800.0, -3600.0, 7000.0}) {
    const auto p = orbits->position(0, toe_gps_s + tk);
    ASSERT_TRUE(p) << tk;
    const sky::Ecef expected = is_gps_200(k, tk);
    EXPECT_LT(distance_m(*p, expected), 0.01) << tk;
    EXPECT_NEAR(std::hypot(p->x_m, p->y_m, p->z_m), 26.56e6, 0.4e6);
  }
  EXPECT_FALSE(orbits->position(0, toe_gps_s + 3 * 3600.0)) << "older than RTKLIB's 2 h limit: no orbit";
}

TEST(SkyOrbits, UnreadableEphemerisIsOneClearError) {
  const auto path = std::filesystem::temp_directory_path() / ("gpsemu_sky_bad_" + std::to_string(::getpid()) + ".rnx");
  std::ofstream(path) << "not a rinex file\n";
  try {
    (void)sky::Orbits::from_rinex_nav(path.string());
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

// --- The embedded two-line elements against Kepler + J2 ---------------------------------------

struct Tle {
  double epoch_unix_s = 0, inc = 0, raan = 0, ecc = 0, argp = 0, m = 0, n_rev_day = 0;
};

std::map<std::string, Tle> embedded_tles_by_catalogue() {
  std::map<std::string, Tle> out;
  std::istringstream in{std::string(sky::embedded_tle_text())};
  std::string l0, l1, l2;
  while (std::getline(in, l0) && std::getline(in, l1) && std::getline(in, l2)) {
    Tle t;
    const int yy = std::stoi(l1.substr(18, 2));
    const double doy = std::stod(l1.substr(20, 12));
    // Days from 1970-01-01 to Jan 1 of 20yy.
    int days = 0;
    for (int y = 1970; y < 2000 + yy; ++y) days += (y % 4 == 0 && (y % 100 != 0 || y % 400 == 0)) ? 366 : 365;
    t.epoch_unix_s = (days + doy - 1.0) * 86400.0;
    t.inc = std::stod(l2.substr(8, 8)) * kDeg;
    t.raan = std::stod(l2.substr(17, 8)) * kDeg;
    t.ecc = std::stod("0." + l2.substr(26, 7));
    t.argp = std::stod(l2.substr(34, 8)) * kDeg;
    t.m = std::stod(l2.substr(43, 8)) * kDeg;
    t.n_rev_day = std::stod(l2.substr(52, 11));
    out[l1.substr(2, 5)] = t;
  }
  return out;
}

sky::Ecef kepler_j2_ecef(const Tle& t, double unix_s) {
  constexpr double j2 = 1.08262668e-3, re = 6378137.0, mu = 3.986004418e14;
  const double n = t.n_rev_day * 2 * kPi / 86400.0;
  const double a = std::cbrt(mu / (n * n));
  const double p = a * (1 - t.ecc * t.ecc);
  const double k = 1.5 * j2 * (re / p) * (re / p) * n;
  const double dt = unix_s - t.epoch_unix_s;
  const double raan = t.raan - k * std::cos(t.inc) * dt;
  const double argp = t.argp + 0.5 * k * (5 * std::cos(t.inc) * std::cos(t.inc) - 1) * dt;
  const double m = t.m + n * dt;
  double ea = m;
  for (int i = 0; i < 30; ++i) ea = m + t.ecc * std::sin(ea);
  const double nu = std::atan2(std::sqrt(1 - t.ecc * t.ecc) * std::sin(ea), std::cos(ea) - t.ecc);
  const double r = a * (1 - t.ecc * std::cos(ea));
  const double u = argp + nu;
  const double x = r * (std::cos(raan) * std::cos(u) - std::sin(raan) * std::sin(u) * std::cos(t.inc));
  const double y = r * (std::sin(raan) * std::cos(u) + std::cos(raan) * std::sin(u) * std::cos(t.inc));
  const double z = r * std::sin(u) * std::sin(t.inc);
  // TEME to earth-fixed: rotate by Greenwich mean sidereal time (UT1 ~ UTC, no polar motion).
  const double jd = unix_s / 86400.0 + 2440587.5;
  const double gmst = std::fmod(280.46061837 + 360.98564736629 * (jd - 2451545.0), 360.0) * kDeg;
  return {std::cos(gmst) * x + std::sin(gmst) * y, -std::sin(gmst) * x + std::cos(gmst) * y, z};
}

TEST(SkyOrbits, EmbeddedSkyHasFourSystemsFromRinexAndQzssSbasFromElements) {
  const auto orbits = sky::Orbits::embedded_default();
  std::map<nmea::GnssSystem, int> per_system;
  for (const auto& id : orbits->satellites()) ++per_system[id.system];
  EXPECT_GE(per_system[nmea::GnssSystem::gps], 30);
  EXPECT_GE(per_system[nmea::GnssSystem::glonass], 20);
  EXPECT_GE(per_system[nmea::GnssSystem::galileo], 12);  // 14 healthy in 2018
  EXPECT_GE(per_system[nmea::GnssSystem::beidou], 5);  // what a station in Nevada received in 2018
  EXPECT_GE(per_system[nmea::GnssSystem::qzss], 3);
  EXPECT_GE(per_system[nmea::GnssSystem::sbas], 5);
  // The RINEX file's day (2018-07-29: most of its records; it starts the evening before).
  EXPECT_EQ(orbits->coverage_start(), gps_seconds_of(parse_iso8601_utc("2018-07-28T23:59:42Z")))
      << "00:00 GPS time (18 leap seconds ahead of UTC)";
}

// QZSS and SBAS come from the two-line elements of another day, at the same sidereal time: at the
// elements' own moment, they are where Kepler + J2 from the same elements puts them.
TEST(SkyOrbits, EmbeddedElementsAgreeWithKeplerAndJ2AtTheSameSiderealTime) {
  const auto orbits = sky::Orbits::embedded_default();
  const auto tles = embedded_tles_by_catalogue();
  std::map<std::string, std::string> catalogue_of;  // "J02" -> "42738"
  std::istringstream names{std::string(sky::embedded_tle_names_text())};
  for (std::string line; std::getline(names, line);) {
    std::istringstream f(line);
    std::string name, cat;
    if (f >> name >> cat) catalogue_of[name] = cat.substr(0, 5);
  }
  const double unix_s = 1606802400.0;  // 2020-12-01T06:00:00Z, within hours of the elements' epochs
  const double gps_s = unix_s - 315964800.0 + 18.0;
  int checked = 0;
  for (std::size_t i = 0; i < orbits->satellites().size(); ++i) {
    const auto& id = orbits->satellites()[i];
    if (id.system != nmea::GnssSystem::qzss) continue;
    char name[8];
    std::snprintf(name, sizeof name, "J%02d", id.sv_id);
    const auto tle = tles.find(catalogue_of[name]);
    ASSERT_NE(tle, tles.end()) << name;
    if (std::fabs(tle->second.epoch_unix_s - unix_s) > 1.5 * 86400.0) continue;
    // The moment of the RINEX day with this sidereal time is 2020-12-01T06:00 for the elements.
    const auto p = orbits->position(i, orbits->map_time(gps_s));
    ASSERT_TRUE(p) << name;
    const sky::Ecef k = kepler_j2_ecef(tle->second, unix_s);
    // SGP4's deep-space terms (sun, moon) against none: tens of km, 0.1 degree seen from Earth.
    EXPECT_LT(distance_m(*p, k), 100e3) << name;
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

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

TEST(SkyOrbits, AnyDateMapsToTheDataDayAtTheSameSiderealTime) {
  const auto orbits = sky::Orbits::embedded_default();
  const double start = orbits->coverage_start();
  const double t = gps_seconds_of(parse_iso8601_utc("2024-05-01T12:00:00Z"));
  const double m = orbits->map_time(t);
  EXPECT_GE(m, start);
  EXPECT_LT(m, start + sky::kSiderealDayS);
  EXPECT_NEAR(orbits->map_time(t + sky::kSiderealDayS), m, 1e-6) << "a sidereal day later: the same sky";
  EXPECT_NEAR(orbits->map_time(t + 10.0), m + 10.0, 1e-6) << "time runs on";
  EXPECT_EQ(orbits->map_time(start + 3600.0), start + 3600.0) << "the data's own day is its true sky";
}

// --- DOP -----------------------------------------------------------------------------------

TEST(SkyDop, OneSystemMatchesRtklibsDops) {
  const std::vector<sky::AzEl> sats{{10, 75}, {80, 30}, {150, 45}, {220, 20}, {300, 55}, {350, 12}, {45, 60}};
  std::vector<sky::UsedSatellite> used;
  for (const auto& s : sats) used.push_back({s.azimuth_deg, s.elevation_deg, nmea::GnssSystem::gps});
  const sky::Dops ours = sky::multi_clock_dops(used);
  const sky::RtklibDops rtk = sky::rtklib_single_clock_dops(sats, 0.0);
  EXPECT_NEAR(ours.gdop, rtk.gdop, 1e-9);
  EXPECT_NEAR(ours.pdop, rtk.pdop, 1e-9);
  EXPECT_NEAR(ours.hdop, rtk.hdop, 1e-9);
  EXPECT_NEAR(ours.vdop, rtk.vdop, 1e-9);
  EXPECT_NEAR(ours.tdop * ours.tdop + ours.pdop * ours.pdop, ours.gdop * ours.gdop, 1e-9);
}

TEST(SkyDop, AClockPerSystemCostsGeometryAndNeedsMoreSatellites) {
  std::vector<sky::UsedSatellite> used{{10, 75, nmea::GnssSystem::gps},     {80, 30, nmea::GnssSystem::gps},
                                       {150, 45, nmea::GnssSystem::gps},    {220, 20, nmea::GnssSystem::glonass},
                                       {300, 55, nmea::GnssSystem::glonass}, {350, 12, nmea::GnssSystem::qzss}};
  const sky::Dops two_clocks = sky::multi_clock_dops(used);
  ASSERT_TRUE(two_clocks.valid());
  for (auto& u : used) u.system = nmea::GnssSystem::gps;
  const sky::Dops one_clock = sky::multi_clock_dops(used);
  EXPECT_GT(two_clocks.pdop, one_clock.pdop) << "an extra unknown can only dilute";
  used.resize(4);
  used[3].system = nmea::GnssSystem::galileo;  // 4 satellites, 5 unknowns
  EXPECT_FALSE(sky::multi_clock_dops(used).valid());
}

// --- The sky of a model ----------------------------------------------------------------------

std::map<nmea::GnssSystem, int> listed_by_system(const nmea::Fix& fix) {
  std::map<nmea::GnssSystem, int> n;
  for (int i = 0; i < fix.satellites_in_view; ++i) ++n[fix.satellites[static_cast<std::size_t>(i)].system];
  return n;
}

nmea::Fix sky_fix(const SkyOptions& o, const char* when = "2024-05-01T12:00:00Z") {
  Sky sky(o, kMadison);
  nmea::Fix fix;
  (void)sky.fill(parse_iso8601_utc(when), {}, fix);
  return fix;
}

TEST(SkyModels, EachModelListsTheSystemsItTracks) {
  SkyOptions m8;
  m8.profile = sky::profile_of(ubx::ReceiverModel::ublox_m8n);
  const auto a = listed_by_system(sky_fix(m8));
  EXPECT_GE(a.at(nmea::GnssSystem::gps), 6);
  EXPECT_GE(a.at(nmea::GnssSystem::glonass), 4);
  EXPECT_EQ(a.count(nmea::GnssSystem::galileo), 0u);
  EXPECT_EQ(a.count(nmea::GnssSystem::beidou), 0u);
  SkyOptions f9;
  f9.profile = sky::profile_of(ubx::ReceiverModel::ublox_f9p);
  const auto b = listed_by_system(sky_fix(f9));
  EXPECT_GE(b.at(nmea::GnssSystem::galileo), 4);
  EXPECT_GE(b.at(nmea::GnssSystem::beidou), 1);  // the 2018 file's: few BeiDou over North America
  EXPECT_EQ(b.at(nmea::GnssSystem::gps), a.at(nmea::GnssSystem::gps)) << "the same sky";
}

TEST(SkyModels, MaskObstructionAndChannelsDecideWhatIsUsed) {
  SkyOptions o;
  o.profile = sky::profile_of(ubx::ReceiverModel::ublox_f9p);
  Sky open(o, kMadison);
  nmea::Fix fix;
  const SkyState all = open.fill(parse_iso8601_utc("2024-05-01T12:00:00Z"), {}, fix);
  EXPECT_GE(all.used, 20);
  EXPECT_LT(all.dops.hdop, 1.0);
  for (int i = 0; i < fix.satellites_in_view; ++i) {
    const auto& s = fix.satellites[static_cast<std::size_t>(i)];
    if (s.elevation_deg < 4) {
      EXPECT_FALSE(s.used) << "below the 5 degree mask";
    }
  }
  // The satellites' C/N0 grows with elevation.
  double low = 0, high = 0;
  int nl = 0, nh = 0;
  for (int i = 0; i < fix.satellites_in_view; ++i) {
    const auto& s = fix.satellites[static_cast<std::size_t>(i)];
    if (s.system == nmea::GnssSystem::sbas) continue;
    if (s.elevation_deg < 20) low += *s.snr_dbhz, ++nl;
    if (s.elevation_deg > 60) high += *s.snr_dbhz, ++nh;
  }
  ASSERT_GT(nl * nh, 0);
  EXPECT_GT(high / nh, low / nl + 8.0);

  o.profile.elevation_mask_deg = 30.0;
  Sky masked(o, kMadison);
  const SkyState m = masked.fill(parse_iso8601_utc("2024-05-01T12:00:00Z"), {}, fix);
  EXPECT_LT(m.used, all.used);
  EXPECT_GT(m.dops.hdop, all.dops.hdop);
  EXPECT_EQ(m.listed, all.listed) << "below the mask: tracked, not used";

  o.profile.elevation_mask_deg = 5.0;
  o.obstruction = parse_sky_mask("urban-canyon");
  Sky canyon(o, kMadison);
  const SkyState c = canyon.fill(parse_iso8601_utc("2024-05-01T12:00:00Z"), {}, fix);
  EXPECT_LT(c.listed, all.listed);
  EXPECT_GT(c.dops.hdop, all.dops.hdop);
  for (int i = 0; i < fix.satellites_in_view; ++i) {
    const auto& s = fix.satellites[static_cast<std::size_t>(i)];
    const bool across = (s.azimuth_deg > 21 && s.azimuth_deg < 159) || (s.azimuth_deg > 201 && s.azimuth_deg < 339);
    if (across) {
      EXPECT_GE(s.elevation_deg, 44) << "behind the buildings";
    }
  }

  o.obstruction.clear();
  o.profile.channels = 20;  // dual band: 10 satellites
  Sky few(o, kMadison);
  const SkyState f = few.fill(parse_iso8601_utc("2024-05-01T12:00:00Z"), {}, fix);
  EXPECT_EQ(f.listed, 10);
}

TEST(SkyModels, SkyMaskSpecsAreParsedOrRefusedWithTheReason) {
  const auto s = parse_sky_mask("0-90:30,270-45:15");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[1].from_azimuth_deg, 270.0);
  EXPECT_EQ(s[1].to_azimuth_deg, 45.0);
  EXPECT_EQ(s[1].min_elevation_deg, 15.0);
  EXPECT_TRUE(parse_sky_mask("open").empty());
  EXPECT_THROW((void)parse_sky_mask("0-90"), std::invalid_argument);
  EXPECT_THROW((void)parse_sky_mask("0-400:10"), std::invalid_argument);
  EXPECT_THROW((void)parse_sky_mask("a-90:10"), std::invalid_argument);
}

TEST(SkyModels, GeoidIsEgm96) {
  EXPECT_NEAR(sky::geoid_separation_m(43.0725, -89.4125), -33.9, 1.5);  // Madison
  EXPECT_NEAR(sky::geoid_separation_m(0.0, 0.0), 17.2, 1.5);            // EGM96 at 0,0: 17.16 m
  EXPECT_NEAR(sky::geoid_separation_m(35.36, 138.73), 41.0, 3.0);       // Mount Fuji: about 41 m
}

}  // namespace
}  // namespace gpsemu
