// The moving base's RTCM 3 epoch (see rtcm3_base.hpp).
#include "emulator/heading/rtcm3_base.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "emulator/model/sky/orbits.hpp"
#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/rtcm3_msm.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"
#include "emulator/model/gps_time.hpp"

namespace gpsemu::heading {
namespace {

constexpr double kEarthRadiusM = 6371000.0;
constexpr std::uint32_t kLockedMs = 524288;  // DF402 15: locked for at least 524 s

struct SystemInfo {
  nmea::GnssSystem system;
  rtk::Gnss gnss;
  double orbit_radius_m;
};
// In output order: GPS, GLONASS, Galileo, QZSS, BeiDou.
constexpr std::array<SystemInfo, 5> kSystems = {{{nmea::GnssSystem::gps, rtk::Gnss::gps, 26560e3},
                                                 {nmea::GnssSystem::glonass, rtk::Gnss::glonass, 25510e3},
                                                 {nmea::GnssSystem::galileo, rtk::Gnss::galileo, 29600e3},
                                                 {nmea::GnssSystem::qzss, rtk::Gnss::qzss, 42164e3},
                                                 {nmea::GnssSystem::beidou, rtk::Gnss::beidou, 27906e3}}};

/// Geometric range (metres) to a satellite at `elevation_deg` on an orbit of radius `orbit_m`.
double range_m(double elevation_deg, double orbit_m) {
  const double el = elevation_deg * std::numbers::pi / 180.0;
  const double c = kEarthRadiusM * std::cos(el);
  return std::sqrt(orbit_m * orbit_m - c * c) - kEarthRadiusM * std::sin(el);
}

std::string msm4(const SystemInfo& info, const std::vector<const nmea::SatelliteInView*>& sats, bool more,
                 std::uint16_t station, const nmea::Fix& fix) {
  rtk::MsmMessage m;
  m.gnss = info.gnss;
  m.msm = 4;
  m.station_id = station;
  m.epoch_time = rtk::msm_epoch_time(info.gnss, fix.time_utc, fix.leap.gps_minus_utc_s);
  m.more_follow = more;
  m.signal_ids = rtk::msm_signal_ids(info.gnss, /*dual_band=*/false);
  for (const auto* s : sats) {
    m.satellites.push_back({.sv_id = s->sv_id,
                            .range_m = range_m(s->elevation_deg, info.orbit_radius_m),
                            .cn0_dbhz = static_cast<double>(*s->snr_dbhz),
                            .lock_ms = kLockedMs,
                            .glonass_channel = std::nullopt});
  }
  return rtk::rtcm3_frame_bytes(rtk::encode_msm_observations(m));
}

std::string type4072_0(const nmea::Fix& fix, std::uint16_t station) {
  rtk::BitWriter w;
  w.u(4072, 12);
  w.u(0, 12);  // sub-type 0: reference station PVT
  w.u(station, 12);
  w.u(gps_time(fix).tow_ms, 30);
  const sky::Ecef e = sky::to_ecef(fix.lat_deg, fix.lon_deg, fix.alt_msl_m + fix.geoid_sep_m);
  for (const double c : {e.x_m, e.y_m, e.z_m}) w.s(std::llround(c * 1e4), 38);
  return rtk::rtcm3_frame_bytes(w.bytes());
}

}  // namespace

int msm4_message_number(nmea::GnssSystem system) {
  const std::optional<rtk::Gnss> gnss = rtk::msm_gnss_of(system);
  return gnss ? rtk::msm_message_type(*gnss, 4) : 0;
}

std::string base_rtcm3_epoch(const nmea::Fix& fix, std::uint16_t station_id) {
  if (!fix.has_fix()) return {};
  std::string out = type4072_0(fix, station_id);
  std::vector<std::pair<const SystemInfo*, std::vector<const nmea::SatelliteInView*>>> groups;
  for (const SystemInfo& info : kSystems) {
    std::vector<const nmea::SatelliteInView*> sats;
    for (int i = 0; i < fix.satellites_in_view && i < static_cast<int>(nmea::max_satellites); ++i) {
      const nmea::SatelliteInView& s = fix.satellites[static_cast<std::size_t>(i)];
      if (s.system == info.system && s.snr_dbhz && s.sv_id >= 1 && s.sv_id <= 64 && s.elevation_deg >= 0) sats.push_back(&s);
    }
    // At most 64 cells a message; one signal a satellite keeps every system within that.
    if (!sats.empty()) groups.emplace_back(&info, std::move(sats));
  }
  for (std::size_t g = 0; g < groups.size(); ++g) {
    out += msm4(*groups[g].first, groups[g].second, g + 1 < groups.size(), station_id, fix);
  }
  out += rtk::rtcm3_frame_bytes(rtk::encode_1230(station_id));
  return out;
}

}  // namespace gpsemu::heading
