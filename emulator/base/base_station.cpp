// A simulated RTK reference station (see base_station.hpp).
#include "emulator/base/base_station.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/model/sky/orbits.hpp"
#include "emulator/model/receiver_models.hpp"
#include "emulator/rtk/rtcm3_msm.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"

namespace gpsemu::base {
namespace {

constexpr double kLightMps = 299792458.0;
constexpr double kEarthRotationRadPerS = 7.2921151467e-5;  // WGS84
constexpr double kMaxAntennaHeightM = 6.5535;              // DF028: 16 bits of 0.1 mm

/// GLONASS frequency channel by orbital slot 1..24: the constellation's plan (antipodal slots share a
/// channel), as broadcast in the almanac; DF419 of MSM7.
constexpr std::array<int, 24> kGlonassChannelBySlot = {1, -4, 5, 6, 1, -4, 5, 6, -2, -7, 0, -1,
                                                       -2, -7, 0, -1, 4, -3, 3, 2, 4, -3, 3, 2};

constexpr std::array<std::pair<rtk::Gnss, const char*>, 5> kSystemNames = {
    {{rtk::Gnss::gps, "GPS"}, {rtk::Gnss::glonass, "GLONASS"}, {rtk::Gnss::galileo, "Galileo"},
     {rtk::Gnss::qzss, "QZSS"}, {rtk::Gnss::beidou, "BeiDou"}}};

std::pair<int, int> key(nmea::GnssSystem system, int sv_id) { return {static_cast<int>(system), sv_id}; }

double distance_m(const sky::Ecef& a, const sky::Ecef& b) { return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m, a.z_m - b.z_m); }

SkyOptions sky_options(const BaseSettings& s) {
  SkyOptions o;
  o.orbits = s.orbits;
  o.tracking = facts_of(ReceiverModel::ublox_f9p).tracking;
  if (s.elevation_mask_deg) o.tracking.elevation_mask_deg = *s.elevation_mask_deg;
  o.seed = s.seed;
  return o;
}

Geodetic ellipsoidal(const Geodetic& msl) {
  return {msl.lat_deg, msl.lon_deg, msl.alt_m + sky::geoid_separation_m(msl.lat_deg, msl.lon_deg)};
}

rtk::BasePosition arp_of(const BaseSettings& s) {
  if (s.msm != 4 && s.msm != 7) throw std::invalid_argument(fmt::format("msm: expected 4 or 7, got {}", s.msm));
  if (s.station_id > 4095) throw std::invalid_argument(fmt::format("station-id: expected 0..4095, got {}", s.station_id));
  if (s.antenna_height_m && !(*s.antenna_height_m >= 0.0 && *s.antenna_height_m <= kMaxAntennaHeightM)) {
    throw std::invalid_argument(
        fmt::format("antenna-height: expected 0..{} metres (1006's 16 bits of 0.1 mm), got {}", kMaxAntennaHeightM, *s.antenna_height_m));
  }
  const Geodetic e = ellipsoidal(s.arp);
  const sky::Ecef x = sky::to_ecef(e.lat_deg, e.lon_deg, e.alt_m);
  return {s.station_id, x.x_m, x.y_m, x.z_m, s.antenna_height_m.value_or(0.0)};
}

}  // namespace

std::vector<rtk::Gnss> parse_systems(const std::string& text) {
  std::vector<bool> chosen(kSystemNames.size(), false);
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    std::string name = text.substr(start, comma - start);
    std::erase_if(name, [](unsigned char c) { return std::isspace(c) != 0; });
    const auto it = std::find_if(kSystemNames.begin(), kSystemNames.end(), [&](const auto& s) {
      return std::equal(name.begin(), name.end(), std::string_view(s.second).begin(), std::string_view(s.second).end(),
                        [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b)); });
    });
    if (it == kSystemNames.end()) {
      throw std::invalid_argument(fmt::format("systems: unknown system '{}' in '{}' (accepted: GPS, GLONASS, Galileo, "
                                              "BeiDou, QZSS)", name, text));
    }
    chosen[static_cast<std::size_t>(it - kSystemNames.begin())] = true;
    start = comma + 1;
  }
  std::vector<rtk::Gnss> out;
  for (std::size_t i = 0; i < kSystemNames.size(); ++i) {
    if (chosen[i]) out.push_back(kSystemNames[i].first);
  }
  return out;
}

BaseStation::BaseStation(const BaseSettings& settings)
    : settings_(settings), position_(arp_of(settings)), sky_(sky_options(settings), ellipsoidal(settings.arp)) {
  const auto& sats = sky_.orbits().satellites();
  for (std::size_t i = 0; i < sats.size(); ++i) orbit_index_[key(sats[i].system, sats[i].sv_id)] = i;
}

BaseEpoch BaseStation::epoch(UtcNs t) {
  BaseEpoch out;
  const auto frame = [&out](const std::string& payload) {
    rtk::append_rtcm3_frame(out.bytes, payload);
    out.types.push_back(rtk::Rtcm3Frame{payload}.message_type());
  };
  frame(rtk::encode_base_position(position_, settings_.antenna_height_m.has_value()));

  nmea::Fix fix;
  const nmea::UtcTime utc = std::chrono::floor<std::chrono::milliseconds>(t);
  fix.time_utc = utc;
  (void)sky_.fill(t, Sky::Tracking{}, fix);
  const sky::Orbits& orbits = sky_.orbits();
  const sky::Ecef arp{position_.ecef_x_m, position_.ecef_y_m, position_.ecef_z_m};
  const double mapped = orbits.map_time(gps_seconds_of(t));

  std::vector<rtk::MsmMessage> messages;
  std::map<std::pair<int, int>, UtcNs> seen;
  for (const rtk::Gnss gnss : settings_.systems) {
    rtk::MsmMessage m;
    m.gnss = gnss;
    m.msm = settings_.msm;
    m.station_id = settings_.station_id;
    m.epoch_time = rtk::msm_epoch_time(gnss, utc);
    m.signal_ids = rtk::msm_signal_ids(gnss, settings_.dual_band);
    const std::size_t most = 64 / m.signal_ids.size();
    for (int i = 0; i < fix.satellites_in_view && i < static_cast<int>(nmea::max_satellites); ++i) {
      const nmea::SatelliteInView& s = fix.satellites[static_cast<std::size_t>(i)];
      if (rtk::msm_gnss_of(s.system) != gnss || !s.used || !s.snr_dbhz || m.satellites.size() >= most) continue;
      const auto k = key(s.system, s.sv_id);
      const auto index = orbit_index_.find(k);
      if (seen.contains(k) || index == orbit_index_.end()) continue;
      const std::optional<sky::EcefMotion> now = orbits.motion(index->second, mapped);
      if (!now) continue;
      // Light time: where the satellite was when the signal left, turned with the Earth meanwhile.
      const double tau_s = distance_m(now->position, arp) / kLightMps;
      const std::optional<sky::Ecef> sent = orbits.position(index->second, mapped - tau_s);
      if (!sent) continue;
      const double turn = kEarthRotationRadPerS * tau_s;
      const sky::Ecef rotated{sent->x_m * std::cos(turn) + sent->y_m * std::sin(turn),
                              -sent->x_m * std::sin(turn) + sent->y_m * std::cos(turn), sent->z_m};
      const double range_m = distance_m(rotated, arp);
      const double los = distance_m(now->position, arp);
      const double rate_mps = (now->vx_mps * (now->position.x_m - arp.x_m) + now->vy_mps * (now->position.y_m - arp.y_m) +
                               now->vz_mps * (now->position.z_m - arp.z_m)) / los;
      const UtcNs first = first_seen_.contains(k) ? first_seen_.at(k) : t;
      seen[k] = first;
      rtk::MsmSatellite sat;
      sat.sv_id = s.sv_id;
      sat.range_m = range_m;
      sat.range_rate_mps = rate_mps;
      sat.cn0_dbhz = static_cast<double>(*s.snr_dbhz);
      sat.lock_ms = static_cast<std::uint32_t>(std::min<std::int64_t>(
          std::chrono::duration_cast<std::chrono::milliseconds>(t - first).count(), 0xFFFFFFFF));
      if (gnss == rtk::Gnss::glonass && s.sv_id >= 1 && s.sv_id <= 24) {
        sat.glonass_channel = kGlonassChannelBySlot[static_cast<std::size_t>(s.sv_id - 1)];
      }
      m.satellites.push_back(sat);
    }
    out.satellites += static_cast<int>(m.satellites.size());
    if (!m.satellites.empty()) messages.push_back(std::move(m));
  }
  first_seen_ = std::move(seen);  // a satellite that set and rose again is locked anew
  for (std::size_t i = 0; i < messages.size(); ++i) {
    messages[i].more_follow = i + 1 < messages.size();
    frame(rtk::encode_msm_observations(messages[i]));
  }
  // GLONASS code-phase biases of the signals observed (an F9P base: L1 C/A and L2 C/A), 0 m: its
  // phase ranges are geometric. (RTKLIB 2.4.3 also reads a 1230 without any bias as too short.)
  frame(rtk::encode_1230(settings_.station_id, settings_.dual_band ? 0b1010u : 0b1000u));
  return out;
}

}  // namespace gpsemu::base
