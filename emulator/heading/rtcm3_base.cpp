// The moving base's RTCM 3 epoch (see rtcm3_base.hpp).
#include "emulator/heading/rtcm3_base.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

#include "emulator/model/sky/orbits.hpp"
#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"
#include "emulator/ubx/nav.hpp"

namespace gpsemu::heading {
namespace {

constexpr double kLightMetresPerMs = 299792.458;
constexpr double kEarthRadiusM = 6371000.0;
constexpr int kSignalId = 2;  // 1C (GPS, Galileo, QZSS), G1 C/A, B1I ("2I"): DF395 bit 2
constexpr std::uint32_t kWeekMs = 7u * 24u * 3600u * 1000u;

struct SystemInfo {
  nmea::GnssSystem system;
  int message;
  double orbit_radius_m;
};
// In output order: GPS, GLONASS, Galileo, QZSS, BeiDou.
constexpr std::array<SystemInfo, 5> kSystems = {{{nmea::GnssSystem::gps, 1074, 26560e3},
                                                 {nmea::GnssSystem::glonass, 1084, 25510e3},
                                                 {nmea::GnssSystem::galileo, 1094, 29600e3},
                                                 {nmea::GnssSystem::qzss, 1114, 42164e3},
                                                 {nmea::GnssSystem::beidou, 1124, 27906e3}}};

/// Geometric range (metres) to a satellite at `elevation_deg` on an orbit of radius `orbit_m`.
double range_m(double elevation_deg, double orbit_m) {
  const double el = elevation_deg * std::numbers::pi / 180.0;
  const double c = kEarthRadiusM * std::cos(el);
  return std::sqrt(orbit_m * orbit_m - c * c) - kEarthRadiusM * std::sin(el);
}

/// The system's 30-bit epoch time field.
std::uint32_t epoch_time_field(nmea::GnssSystem system, const nmea::UtcTime& utc) {
  const std::uint32_t gps_tow_ms = ubx::gps_time(utc).tow_ms;
  if (system == nmea::GnssSystem::beidou) return (gps_tow_ms + kWeekMs - 14000u) % kWeekMs;
  if (system == nmea::GnssSystem::glonass) {
    using namespace std::chrono;
    const auto moscow = utc + hours{3};
    const auto day = floor<days>(moscow);
    const auto dow = static_cast<std::uint32_t>(weekday{day}.c_encoding());  // 0 = Sunday, as DF416
    const auto tod_ms = static_cast<std::uint32_t>(duration_cast<milliseconds>(moscow - day).count());
    return (dow << 27) | tod_ms;
  }
  return gps_tow_ms;
}

std::string msm4(const SystemInfo& info, const std::vector<const nmea::SatelliteInView*>& sats, bool more,
                 std::uint16_t station, const nmea::UtcTime& utc) {
  rtk::BitWriter w;
  w.u(static_cast<std::uint64_t>(info.message), 12);
  w.u(station, 12);
  w.u(epoch_time_field(info.system, utc), 30);
  w.u(more ? 1 : 0, 1);  // DF393 multiple message bit
  w.u(0, 3);             // DF409 IODS
  w.u(0, 7);             // DF001 reserved
  w.u(0, 2);             // DF411 clock steering
  w.u(0, 2);             // DF412 external clock
  w.u(0, 1);             // DF417 smoothing
  w.u(0, 3);             // DF418 smoothing interval
  std::uint64_t sat_mask = 0;
  for (const auto* s : sats) sat_mask |= 1ull << (64 - s->sv_id);
  w.u(sat_mask, 64);
  w.u(1ull << (32 - kSignalId), 32);
  for (std::size_t i = 0; i < sats.size(); ++i) w.u(1, 1);  // one signal a satellite: every cell
  // Satellites in mask order (ascending ID).
  std::vector<const nmea::SatelliteInView*> ordered = sats;
  std::sort(ordered.begin(), ordered.end(), [](const auto* a, const auto* b) { return a->sv_id < b->sv_id; });
  std::vector<double> range_ms;
  for (const auto* s : ordered) range_ms.push_back(range_m(s->elevation_deg, info.orbit_radius_m) / kLightMetresPerMs);
  std::vector<double> rough_ms;
  for (const double r : range_ms) {
    const double rough = std::floor(r * 1024.0) / 1024.0;
    rough_ms.push_back(rough);
    w.u(static_cast<std::uint64_t>(std::floor(rough)), 8);  // DF397
  }
  for (const double rough : rough_ms) {
    w.u(static_cast<std::uint64_t>(std::lround((rough - std::floor(rough)) * 1024.0)) & 0x3FF, 10);  // DF398
  }
  for (std::size_t i = 0; i < ordered.size(); ++i) {
    w.s(std::llround((range_ms[i] - rough_ms[i]) * 0x1p24), 15);  // DF400 fine pseudorange, 2^-24 ms
  }
  for (std::size_t i = 0; i < ordered.size(); ++i) {
    w.s(std::llround((range_ms[i] - rough_ms[i]) * 0x1p29), 22);  // DF401 fine phaserange, 2^-29 ms
  }
  for (std::size_t i = 0; i < ordered.size(); ++i) w.u(15, 4);  // DF402 lock time indicator 15: locked >= 524 s
  for (std::size_t i = 0; i < ordered.size(); ++i) w.u(0, 1);   // DF420 half-cycle resolved
  for (const auto* s : ordered) w.u(static_cast<std::uint64_t>(std::clamp(*s->snr_dbhz, 0, 63)), 6);  // DF403
  return rtk::rtcm3_frame_bytes(w.bytes());
}

std::string type4072_0(const nmea::Fix& fix, std::uint16_t station) {
  rtk::BitWriter w;
  w.u(4072, 12);
  w.u(0, 12);  // sub-type 0: reference station PVT
  w.u(station, 12);
  w.u(ubx::gps_time(fix).tow_ms, 30);
  const sky::Ecef e = sky::to_ecef(fix.lat_deg, fix.lon_deg, fix.alt_msl_m + fix.geoid_sep_m);
  for (const double c : {e.x_m, e.y_m, e.z_m}) w.s(std::llround(c * 1e4), 38);
  return rtk::rtcm3_frame_bytes(w.bytes());
}

}  // namespace

int msm4_message_number(nmea::GnssSystem system) {
  for (const SystemInfo& s : kSystems) {
    if (s.system == system) return s.message;
  }
  return 0;
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
    out += msm4(*groups[g].first, groups[g].second, g + 1 < groups.size(), station_id, fix.time_utc);
  }
  out += rtk::rtcm3_frame_bytes(rtk::encode_1230(station_id));
  return out;
}

}  // namespace gpsemu::heading
