// The sky: orbits from RTKLIB checked against independent computations (the IS-GPS-200 ephemeris
// algorithm of sky_kepler.hpp for a RINEX record, with GeographicLib for azimuth/elevation; the
// embedded file's real records in sky_records_test.cpp; Kepler with J2 secular rates and a GMST
// rotation for the embedded two-line elements), the
// multi-clock DOP against RTKLIB's single-clock dops() on one system, and the per-model sky:
// systems, elevation mask, obstruction, channels, C/N0 by elevation.
#include <gtest/gtest.h>

#include <GeographicLib/LocalCartesian.hpp>
#include <algorithm>
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
#include "emulator/model/receiver_models.hpp"
#include "tests/support/scratch.hpp"
#include "tests/unit/model/sky_kepler.hpp"

namespace gpsemu {
namespace {
namespace sky_test {

using namespace sky_test_support;


// --- A RINEX 3 GPS record, and IS-GPS-200's algorithm -----------------------------------------


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


TEST(SkyOrbits, RinexRecordGivesTheIsGps200PositionOfItsEphemeris) {
  const Kepler k;
  const auto path = test::scratch_root() / ("gpsemu_sky_" + std::to_string(::getpid()) + ".rnx");
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
  // Beyond RTKLIB's 2 h limit the nearest record (the only one) is extrapolated: the same
  // IS-GPS-200 orbit, hours on.
  for (const double tk : {3 * 3600.0, -10 * 3600.0}) {
    const auto p = orbits->position(0, toe_gps_s + tk);
    ASSERT_TRUE(p) << tk;
    EXPECT_LT(distance_m(*p, is_gps_200(k, tk)), 0.01) << tk;
  }
}

TEST(SkyOrbits, UnreadableEphemerisIsOneClearError) {
  const auto path = test::scratch_root() / ("gpsemu_sky_bad_" + std::to_string(::getpid()) + ".rnx");
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

TEST(SkyOrbits, EmbeddedSkyHasFiveSystemsFromRinexAndSbasFromElements) {
  const auto orbits = sky::Orbits::embedded_default();
  std::map<nmea::GnssSystem, int> per_system;
  for (const auto& id : orbits->satellites()) ++per_system[id.system];
  // The merged file of 2026-03-09 (data/sky/README.md) has GPS 32, GLONASS 27, Galileo 30,
  // BeiDou 48 and QZSS 5 satellites; the sky keeps those with a healthy record that day: GPS 32,
  // GLONASS 24 (not R26-R28), Galileo 26 (not E14, E18, E28, E32), BeiDou 43 (not C47-C50,
  // C62) and QZSS J02, J03, J07 (not J04, J08), plus the elements' J01.
  EXPECT_GE(per_system[nmea::GnssSystem::gps], 30);
  EXPECT_GE(per_system[nmea::GnssSystem::glonass], 22);
  EXPECT_GE(per_system[nmea::GnssSystem::galileo], 24);
  EXPECT_GE(per_system[nmea::GnssSystem::beidou], 40);  // BDS-2 and BDS-3, GEO and IGSO included
  EXPECT_GE(per_system[nmea::GnssSystem::qzss], 4);
  EXPECT_GE(per_system[nmea::GnssSystem::sbas], 5);
  // The RINEX file's day (2026-03-09: most of its records).
  EXPECT_EQ(orbits->coverage_start(), gps_seconds_of(parse_iso8601_utc("2026-03-08T23:59:42Z")))
      << "00:00 GPS time (18 leap seconds ahead of UTC)";
}

// BeiDou's geostationary satellites (PRN 1-5 and 59-63; RTKLIB rotates their broadcast orbit by
// the 5 degrees of their frame) stay put over the Earth: over the whole day each stays within
// 8 000 km of where it was (an inclination of up to 5 degrees swings it 7 300 km from north to
// south; an inclined geosynchronous orbit of 55 degrees moves 70 000 km, a medium one more), at
// a geostationary radius.
TEST(SkyOrbits, EmbeddedBeidouGeostationarySatellitesStayPut) {
  const auto orbits = sky::Orbits::embedded_default();
  const double start = orbits->coverage_start();
  int geo = 0;
  for (std::size_t i = 0; i < orbits->satellites().size(); ++i) {
    const auto& id = orbits->satellites()[i];
    if (id.system != nmea::GnssSystem::beidou || (id.sv_id > 5 && id.sv_id < 59)) continue;
    const auto first = orbits->position(i, start);
    ASSERT_TRUE(first) << "C" << id.sv_id;
    const double radius_m = std::sqrt(first->x_m * first->x_m + first->y_m * first->y_m + first->z_m * first->z_m);
    EXPECT_NEAR(radius_m, 42164e3, 100e3) << "C" << id.sv_id;
    for (double t = start; t < start + 86400.0; t += 3600.0) {
      const auto p = orbits->position(i, t);
      if (p) {
        EXPECT_LT(distance_m(*p, *first), 8000e3) << "C" << id.sv_id << " at +" << t - start << " s";
      }
    }
    ++geo;
  }
  EXPECT_GE(geo, 3);
}

// The issue-33 acceptance: over a day (every 30 minutes), an F9P (its systems, its 5-degree mask)
// has a median of at least 12 BeiDou satellites above its mask at Tokyo and at least 7 Galileo at
// Madison, Tokyo and Sydney (a 2026 sky: about 8-12 Galileo everywhere, 15-25 BeiDou over Asia
// and Australia).
TEST(SkyOrbits, EmbeddedSkyGivesAnF9pTodaysGalileoEverywhereAndBeidouOverAsia) {
  SkyOptions o;
  o.tracking = facts_of(ReceiverModel::ublox_f9p).tracking;
  const Geodetic tokyo{35.68, 139.77, 40.0}, sydney{-33.87, 151.21, 50.0};
  const auto median_above_mask = [&](const Geodetic& where, nmea::GnssSystem system) {
    std::vector<int> counts;
    for (int half_hour = 0; half_hour < 48; ++half_hour) {
      Sky sky(o, where);
      nmea::Fix fix;
      const UtcNs when = parse_iso8601_utc("2026-06-15T00:00:00Z") + std::chrono::minutes(30 * half_hour);
      (void)sky.fill(when, {}, fix);
      int n = 0;
      for (int i = 0; i < fix.satellites_in_view; ++i) {
        const auto& s = fix.satellites[static_cast<std::size_t>(i)];
        if (s.system == system && s.elevation_deg >= o.tracking.elevation_mask_deg) ++n;
      }
      counts.push_back(n);
    }
    std::sort(counts.begin(), counts.end());
    return (counts[23] + counts[24]) / 2.0;
  };
  const double tokyo_beidou = median_above_mask(tokyo, nmea::GnssSystem::beidou);
  const double madison_galileo = median_above_mask(kMadison, nmea::GnssSystem::galileo);
  const double tokyo_galileo = median_above_mask(tokyo, nmea::GnssSystem::galileo);
  const double sydney_galileo = median_above_mask(sydney, nmea::GnssSystem::galileo);
  std::printf("medians above the mask: Tokyo BeiDou %.1f, Galileo Madison %.1f, Tokyo %.1f, Sydney %.1f\n",
              tokyo_beidou, madison_galileo, tokyo_galileo, sydney_galileo);
  EXPECT_GE(tokyo_beidou, 12.0);
  EXPECT_GE(madison_galileo, 7.0);
  EXPECT_GE(tokyo_galileo, 7.0);
  EXPECT_GE(sydney_galileo, 7.0);
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
  // Dates after the file's (a run in November of the March file) map into its day too.
  const double later = orbits->map_time(gps_seconds_of(parse_iso8601_utc("2026-11-28T10:00:00Z")));
  EXPECT_GE(later, start);
  EXPECT_LT(later, start + sky::kSiderealDayS);
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
  m8.tracking = facts_of(ReceiverModel::ublox_m8n).tracking;
  const auto a = listed_by_system(sky_fix(m8));
  EXPECT_GE(a.at(nmea::GnssSystem::gps), 6);
  EXPECT_GE(a.at(nmea::GnssSystem::glonass), 4);
  EXPECT_EQ(a.count(nmea::GnssSystem::galileo), 0u);
  EXPECT_EQ(a.count(nmea::GnssSystem::beidou), 0u);
  SkyOptions f9;
  f9.tracking = facts_of(ReceiverModel::ublox_f9p).tracking;
  const auto b = listed_by_system(sky_fix(f9));
  EXPECT_GE(b.at(nmea::GnssSystem::galileo), 4);
  EXPECT_GE(b.at(nmea::GnssSystem::beidou), 4);  // BeiDou's medium orbits reach North America too
  EXPECT_EQ(b.at(nmea::GnssSystem::gps), a.at(nmea::GnssSystem::gps)) << "the same sky";
}

TEST(SkyModels, MaskObstructionAndChannelsDecideWhatIsUsed) {
  SkyOptions o;
  o.tracking = facts_of(ReceiverModel::ublox_f9p).tracking;
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

  o.tracking.elevation_mask_deg = 30.0;
  Sky masked(o, kMadison);
  const SkyState m = masked.fill(parse_iso8601_utc("2024-05-01T12:00:00Z"), {}, fix);
  EXPECT_LT(m.used, all.used);
  EXPECT_GT(m.dops.hdop, all.dops.hdop);
  EXPECT_EQ(m.listed, all.listed) << "below the mask: tracked, not used";

  o.tracking.elevation_mask_deg = 5.0;
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
  o.tracking.channels = 20;  // dual band: 10 satellites
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

}  // namespace sky_test
}  // namespace
}  // namespace gpsemu
