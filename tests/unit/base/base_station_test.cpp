// The base station's epoch (`gpsemu base`): 1005 (or 1006 with the antenna height), one MSM4 or MSM7
// per system of its sky with the multiple message bit on all but the last, then 1230; every frame
// read back by the project's RTCM3 reader and decoder (rtk/), the ARP round-tripped through it to
// the geodetic position asked for, and the ranges those of the real orbits (the satellite's
// distance from the ARP, and plausible for its elevation).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

#include <GeographicLib/Geocentric.hpp>

#include "emulator/base/base_station.hpp"
#include "emulator/model/receiver_models.hpp"
#include "emulator/model/sky/orbits.hpp"
#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"

namespace gpsemu::base {
namespace {
namespace base_station_test {

using namespace std::chrono_literals;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

std::vector<rtk::Rtcm3Message> decoded(const BaseEpoch& epoch) {
  rtk::Rtcm3Reader reader;
  std::vector<rtk::Rtcm3Message> out;
  for (const rtk::Rtcm3Frame& f : reader.feed(epoch.bytes)) out.push_back(rtk::decode_rtcm3(f.payload));
  EXPECT_EQ(reader.stats().bad_crc, 0u);
  EXPECT_EQ(reader.stats().garbage_bytes, 0u);
  return out;
}

TEST(BaseStation, AnEpochIs1005ThenOneMsm4PerSystemThen1230) {
  BaseStation station(BaseSettings{});
  const BaseEpoch epoch = station.epoch(kT0);
  const auto messages = decoded(epoch);
  ASSERT_GE(messages.size(), 4u);  // 1005, at least two systems' MSM at Madison, 1230
  EXPECT_EQ(messages.front().type, 1005);
  EXPECT_EQ(messages.back().type, 1230);
  std::vector<std::uint16_t> types;
  int satellites = 0;
  for (std::size_t i = 0; i < messages.size(); ++i) {
    const rtk::Rtcm3Message& m = messages[i];
    types.push_back(m.type);
    EXPECT_TRUE(m.valid) << rtk::describe(m);
    ASSERT_TRUE(m.station_id) << rtk::describe(m);
    EXPECT_EQ(*m.station_id, 0);
    if (i == 0 || i + 1 == messages.size()) continue;
    ASSERT_TRUE(m.msm) << rtk::describe(m);
    EXPECT_EQ(m.msm->msm, 4);
    EXPECT_EQ(m.msm->signals, 2);  // L1 and L2, as an F9P base
    EXPECT_EQ(m.msm->cells, m.msm->satellites * 2);
    EXPECT_EQ(m.msm->more_follow, i + 2 < messages.size()) << rtk::describe(m);
    satellites += m.msm->satellites;
  }
  EXPECT_EQ(types, epoch.types);
  EXPECT_EQ(satellites, epoch.satellites);
  EXPECT_GE(satellites, 12);  // GPS, GLONASS, Galileo and BeiDou above 5 degrees
  // In the order GPS, GLONASS, Galileo, QZSS, BeiDou; GPS and GLONASS are always in view.
  EXPECT_EQ(types[1], 1074);
  EXPECT_EQ(types[2], 1084);
  for (std::size_t i = 2; i + 1 < types.size(); ++i) EXPECT_LT(types[i - 1], types[i]);
}

TEST(BaseStation, The1005PositionRoundTripsThroughTheReader) {
  BaseSettings s;
  s.arp = {52.5163, 13.3777, 34.0};
  s.station_id = 2101;
  BaseStation station(s);
  const auto messages = decoded(station.epoch(kT0));
  ASSERT_FALSE(messages.empty());
  ASSERT_TRUE(messages.front().base);
  const rtk::BasePosition& b = *messages.front().base;
  EXPECT_EQ(b.station_id, 2101);
  EXPECT_EQ(messages.front().type, 1005);
  double lat = 0, lon = 0, h = 0;
  GeographicLib::Geocentric::WGS84().Reverse(b.ecef_x_m, b.ecef_y_m, b.ecef_z_m, lat, lon, h);
  EXPECT_NEAR(lat, 52.5163, 1e-8);  // 0.1 mm of ECEF resolution is ~1e-9 degrees
  EXPECT_NEAR(lon, 13.3777, 1e-8);
  EXPECT_NEAR(h, 34.0 + sky::geoid_separation_m(52.5163, 13.3777), 1e-3);  // MSL + the EGM96 geoid
  EXPECT_NEAR(b.ecef_x_m, station.position().ecef_x_m, 1e-4);
}

TEST(BaseStation, AnAntennaHeightMakesIt1006) {
  BaseSettings s;
  s.antenna_height_m = 1.8;
  BaseStation station(s);
  const auto messages = decoded(station.epoch(kT0));
  ASSERT_TRUE(messages.front().base);
  EXPECT_EQ(messages.front().type, 1006);
  EXPECT_NEAR(messages.front().base->antenna_height_m, 1.8, 1e-4);
}

TEST(BaseStation, Msm7AndASystemChoice) {
  BaseSettings s;
  s.msm = 7;
  s.systems = parse_systems("glonass, GPS");
  BaseStation station(s);
  const auto messages = decoded(station.epoch(kT0));
  std::vector<std::uint16_t> types;
  for (const auto& m : messages) {
    types.push_back(m.type);
    EXPECT_TRUE(m.valid) << rtk::describe(m);
  }
  EXPECT_EQ(types, (std::vector<std::uint16_t>{1005, 1077, 1087, 1230}));
}

TEST(BaseStation, RangesAreTheOrbitsDistances) {
  // GPS MSM4: each satellite's rough range (DF397 whole ms + DF398 1/1024 ms) against the distance of
  // a satellite on a 26 560 km orbit seen at its elevation: within 600 km (an eccentricity of up
  // to 0.02 puts the satellite 530 km off that circle, 550 km of range near the horizon, and the
  // sky's whole degrees of elevation are up to 55 km of range there).
  BaseSettings s;
  s.systems = {rtk::Gnss::gps};
  s.dual_band = false;
  BaseStation station(s);
  const BaseEpoch epoch = station.epoch(kT0);
  rtk::Rtcm3Reader reader;
  const auto frames = reader.feed(epoch.bytes);
  ASSERT_EQ(frames.size(), 3u);
  rtk::BitReader r(frames[1].payload);
  r.skip(12 + 12 + 30 + 1 + 3 + 7 + 2 + 2 + 1 + 3);
  const std::uint64_t mask = r.u(64);
  const int n = std::popcount(mask);
  r.skip(32 + static_cast<std::size_t>(n));
  std::vector<double> range_km(static_cast<std::size_t>(n));
  for (auto& x : range_km) x = static_cast<double>(r.u(8)) * 299.792458;
  for (auto& x : range_km) x += static_cast<double>(r.u(10)) / 1024.0 * 299.792458;
  // The same satellites' elevations, from the emulator's sky at the same place and time.
  SkyOptions o;
  o.tracking = gpsemu::facts_of(gpsemu::ReceiverModel::ublox_f9p).tracking;
  Sky sky(o, {43.0725, -89.4125, 260.0 + sky::geoid_separation_m(43.0725, -89.4125)});
  nmea::Fix fix;
  fix.time_utc = std::chrono::floor<std::chrono::milliseconds>(kT0);
  (void)sky.fill(kT0, Sky::Tracking{}, fix);
  std::size_t k = 0;
  for (int sv = 1; sv <= 64; ++sv) {
    if (!((mask >> (64 - sv)) & 1u)) continue;
    const nmea::SatelliteInView* seen = nullptr;
    for (int i = 0; i < fix.satellites_in_view; ++i) {
      const auto& sat = fix.satellites[static_cast<std::size_t>(i)];
      if (sat.system == nmea::GnssSystem::gps && sat.sv_id == sv) seen = &sat;
    }
    ASSERT_NE(seen, nullptr) << "G" << sv << " is not in the sky";
    const double el = seen->elevation_deg * std::numbers::pi / 180.0, re = 6371.0, orbit = 26560.0;
    const double expected_km = std::sqrt(orbit * orbit - std::pow(re * std::cos(el), 2)) - re * std::sin(el);
    EXPECT_NEAR(range_km[k], expected_km, 600.0) << "G" << sv << " at " << seen->elevation_deg << " degrees";
    // And the satellite's distance at the epoch itself, from the orbits: within the ~300 m it moves
    // while the signal travels (the base writes the range at transmission, rounded to 1/1024 ms).
    const sky::Orbits& orbits = sky.orbits();
    const auto& ids = orbits.satellites();
    const auto at = std::find(ids.begin(), ids.end(), sky::SatelliteId{nmea::GnssSystem::gps, sv});
    ASSERT_NE(at, ids.end());
    const auto p = orbits.position(static_cast<std::size_t>(at - ids.begin()), orbits.map_time(gps_seconds_of(kT0)));
    ASSERT_TRUE(p);
    const rtk::BasePosition& arp = station.position();
    const double now_km = std::hypot(p->x_m - arp.ecef_x_m, p->y_m - arp.ecef_y_m, p->z_m - arp.ecef_z_m) / 1000.0;
    EXPECT_NEAR(range_km[k], now_km, 0.6) << "G" << sv;
    ++k;
  }
  EXPECT_EQ(k, range_km.size());
}

/// The largest DF402 lock time indicator of the GPS MSM4 (the second frame) of `epoch`.
unsigned longest_lock(const BaseEpoch& epoch) {
  rtk::Rtcm3Reader reader;
  const auto frames = reader.feed(epoch.bytes);
  EXPECT_GE(frames.size(), 3u);
  if (frames.size() < 3) return 0;
  rtk::BitReader r(frames[1].payload);
  r.skip(12 + 12 + 30 + 1 + 3 + 7 + 2 + 2 + 1 + 3);
  const auto sats = static_cast<std::size_t>(std::popcount(r.u(64)));
  const auto cells = sats * static_cast<std::size_t>(std::popcount(r.u(32)));
  r.skip(cells + 18 * sats + (15 + 22) * cells);
  unsigned longest = 0;
  for (std::size_t i = 0; i < cells; ++i) longest = std::max(longest, static_cast<unsigned>(r.u(4)));
  return longest;
}

TEST(BaseStation, LockTimesCountFromTheFirstEpoch) {
  BaseSettings s;
  s.systems = {rtk::Gnss::gps};
  BaseStation station(s);
  EXPECT_EQ(longest_lock(station.epoch(kT0)), 0u);  // just started: < 32 ms
  for (int k = 1; k < 40; ++k) (void)station.epoch(kT0 + k * 1s);
  EXPECT_EQ(longest_lock(station.epoch(kT0 + 40s)), 11u);  // 40 s: >= 2^15 ms, < 2^16 ms
}

TEST(BaseStation, BadSettingsAreRefusedNamingThem) {
  BaseSettings s;
  s.msm = 5;
  EXPECT_THROW(BaseStation{s}, std::invalid_argument);
  s = {};
  s.station_id = 4096;
  EXPECT_THROW(BaseStation{s}, std::invalid_argument);
  s = {};
  s.antenna_height_m = 7.0;
  try {
    BaseStation station(s);
    ADD_FAILURE() << "an antenna height of 7 m was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("antenna-height"), std::string::npos) << e.what();
  }
  try {
    (void)parse_systems("GPS,SBAS");
    ADD_FAILURE() << "SBAS was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'SBAS'"), std::string::npos) << e.what();
  }
  EXPECT_EQ(parse_systems("beidou,GPS"), (std::vector<rtk::Gnss>{rtk::Gnss::gps, rtk::Gnss::beidou}));
}

}  // namespace base_station_test
}  // namespace
}  // namespace gpsemu::base
