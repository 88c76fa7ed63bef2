// MSM4/MSM7 observation messages (see rtcm3_msm.hpp).
#include "emulator/rtk/rtcm3_msm.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/model/gps_time.hpp"

namespace gpsemu::rtk {
namespace {

constexpr double kLightMetresPerMs = 299792.458;
constexpr std::uint32_t kWeekMs = 7u * 24u * 3600u * 1000u;

/// Writes `value` (units of `unit`) as a signed field of `bits`, clamped to its range.
void put_scaled(BitWriter& w, double value, double unit, int bits) {
  const std::int64_t most = (std::int64_t{1} << (bits - 1)) - 1;
  w.s(std::clamp<std::int64_t>(std::llround(value / unit), -most, most), bits);
}

}  // namespace

std::uint16_t msm_message_type(Gnss gnss, int msm) {
  static constexpr std::uint16_t kBase[] = {1070, 1080, 1090, 1100, 1110, 1120, 1130};  // Gnss order
  return static_cast<std::uint16_t>(kBase[static_cast<int>(gnss)] + msm);
}

std::optional<Gnss> msm_gnss_of(nmea::GnssSystem system) {
  switch (system) {
    case nmea::GnssSystem::gps: return Gnss::gps;
    case nmea::GnssSystem::glonass: return Gnss::glonass;
    case nmea::GnssSystem::galileo: return Gnss::galileo;
    case nmea::GnssSystem::qzss: return Gnss::qzss;
    case nmea::GnssSystem::beidou: return Gnss::beidou;
    case nmea::GnssSystem::sbas: return std::nullopt;
  }
  return std::nullopt;
}

std::vector<int> msm_signal_ids(Gnss gnss, bool dual_band) {
  // DF395 ids (RTCM 10403.3 tables 3.5-91 .. 3.5-108): 2 is each system's L1 civil signal.
  int second = 0;
  switch (gnss) {
    case Gnss::gps:
    case Gnss::qzss: second = 16; break;    // 2L: L2C (L)
    case Gnss::glonass: second = 8; break;  // 2C: G2 C/A
    case Gnss::galileo: second = 15; break; // 7Q: E5b pilot
    case Gnss::beidou: second = 14; break;  // 7I: B2I
    default: break;
  }
  if (!dual_band || second == 0) return {2};
  return {2, second};
}

std::uint32_t msm_epoch_time(Gnss gnss, nmea::UtcTime utc, int gps_minus_utc_s) {
  const std::uint32_t gps_tow_ms = gps_time(utc, gps_minus_utc_s).tow_ms;
  if (gnss == Gnss::beidou) return (gps_tow_ms + kWeekMs - 14000u) % kWeekMs;
  if (gnss == Gnss::glonass) {
    using namespace std::chrono;
    const auto moscow = utc + hours{3};
    const auto day = floor<days>(moscow);
    const auto dow = static_cast<std::uint32_t>(weekday{day}.c_encoding());  // 0 = Sunday, as DF416
    const auto tod_ms = static_cast<std::uint32_t>(duration_cast<milliseconds>(moscow - day).count());
    return (dow << 27) | tod_ms;
  }
  return gps_tow_ms;
}

unsigned msm_lock_indicator(std::uint32_t lock_ms) {
  // DF402: 0 below 32 ms, else i with lock >= 2^(i+4) ms, at most 15 (524 288 ms).
  if (lock_ms < 32) return 0;
  return std::min(15u, static_cast<unsigned>(std::bit_width(lock_ms)) - 1u - 4u);
}

unsigned msm_lock_indicator_extended(std::uint32_t lock_ms) {
  // DF407 (table 3.5-75): t below 64 ms as is; in [2^k, 2^(k+1)) 32 (k - 4) + (t - 2^k) / 2^(k-5);
  // 704 from 2^26 ms on.
  if (lock_ms < 64) return lock_ms;
  const unsigned k = static_cast<unsigned>(std::bit_width(lock_ms)) - 1u;
  if (k >= 26) return 704;
  return 32u * (k - 4u) + ((lock_ms - (1u << k)) >> (k - 5u));
}

std::string encode_msm_observations(const MsmMessage& m) {
  if (m.msm != 4 && m.msm != 7) throw std::invalid_argument(fmt::format("MSM{}: only MSM4 and MSM7 are written", m.msm));
  std::vector<MsmSatellite> sats = m.satellites;
  std::sort(sats.begin(), sats.end(), [](const auto& a, const auto& b) { return a.sv_id < b.sv_id; });
  std::uint64_t sat_mask = 0;
  for (const MsmSatellite& s : sats) {
    if (s.sv_id < 1 || s.sv_id > 64) throw std::invalid_argument(fmt::format("MSM: satellite id {} outside 1..64", s.sv_id));
    const double ms = s.range_m / kLightMetresPerMs;
    if (!(ms > 0.0 && ms < 255.0)) throw std::invalid_argument(fmt::format("MSM: range {} m outside (0, 255) ms", s.range_m));
    sat_mask |= 1ull << (64 - s.sv_id);
  }
  std::uint32_t sig_mask = 0;
  for (const int id : m.signal_ids) {
    if (id < 1 || id > 32) throw std::invalid_argument(fmt::format("MSM: signal id {} outside 1..32", id));
    sig_mask |= 1u << (32 - id);
  }
  const std::size_t signals = static_cast<std::size_t>(std::popcount(sig_mask));
  const std::size_t cells = sats.size() * signals;
  if (cells > 64) throw std::invalid_argument(fmt::format("MSM: {} cells, at most 64", cells));

  BitWriter w;
  w.u(msm_message_type(m.gnss, m.msm), 12);
  w.u(m.station_id, 12);
  w.u(m.epoch_time, 30);
  w.u(m.more_follow ? 1 : 0, 1);  // DF393 multiple message bit
  w.u(0, 3);                      // DF409 IODS
  w.u(0, 7);                      // DF001 reserved
  w.u(0, 2);                      // DF411 clock steering
  w.u(0, 2);                      // DF412 external clock
  w.u(0, 1);                      // DF417 smoothing
  w.u(0, 3);                      // DF418 smoothing interval
  w.u(sat_mask, 64);
  w.u(sig_mask, 32);
  for (std::size_t i = 0; i < cells; ++i) w.u(1, 1);  // every satellite on every signal

  // Satellite data: the range rounded to 1/1024 ms (RTKLIB's and the receivers' rough range).
  std::vector<double> range_ms, rough_ms;
  for (const MsmSatellite& s : sats) {
    range_ms.push_back(s.range_m / kLightMetresPerMs);
    rough_ms.push_back(std::round(range_ms.back() * 1024.0) / 1024.0);
  }
  for (const double r : rough_ms) w.u(static_cast<std::uint64_t>(std::floor(r)), 8);  // DF397
  if (m.msm == 7) {
    for (const MsmSatellite& s : sats) {
      const bool glonass = m.gnss == Gnss::glonass && s.glonass_channel;
      w.u(glonass ? static_cast<std::uint64_t>(std::clamp(*s.glonass_channel, -7, 6) + 7) : 0u, 4);  // DF419
    }
  }
  for (const double r : rough_ms) w.u(static_cast<std::uint64_t>(std::llround((r - std::floor(r)) * 1024.0)) & 0x3FF, 10);  // DF398
  if (m.msm == 7) {
    for (const MsmSatellite& s : sats) put_scaled(w, std::round(s.range_rate_mps), 1.0, 14);  // DF399
  }

  // Cell data, satellite by satellite, each satellite's signals in mask order.
  const auto each_cell = [&](auto&& write) {
    for (std::size_t i = 0; i < sats.size(); ++i) {
      for (std::size_t j = 0; j < signals; ++j) write(i);
    }
  };
  if (m.msm == 4) {
    each_cell([&](std::size_t i) { put_scaled(w, range_ms[i] - rough_ms[i], 0x1p-24, 15); });  // DF400
    each_cell([&](std::size_t i) { put_scaled(w, range_ms[i] - rough_ms[i], 0x1p-29, 22); });  // DF401
    each_cell([&](std::size_t i) { w.u(msm_lock_indicator(sats[i].lock_ms), 4); });            // DF402
    each_cell([&](std::size_t) { w.u(0, 1); });                                                 // DF420
    each_cell([&](std::size_t i) { w.u(static_cast<std::uint64_t>(std::clamp(std::lround(sats[i].cn0_dbhz), 0L, 63L)), 6); });  // DF403
  } else {
    each_cell([&](std::size_t i) { put_scaled(w, range_ms[i] - rough_ms[i], 0x1p-29, 20); });  // DF405
    each_cell([&](std::size_t i) { put_scaled(w, range_ms[i] - rough_ms[i], 0x1p-31, 24); });  // DF406
    each_cell([&](std::size_t i) { w.u(msm_lock_indicator_extended(sats[i].lock_ms), 10); });  // DF407
    each_cell([&](std::size_t) { w.u(0, 1); });                                                 // DF420
    each_cell([&](std::size_t i) {
      w.u(static_cast<std::uint64_t>(std::clamp(std::lround(sats[i].cn0_dbhz * 16.0), 0L, 1023L)), 10);  // DF408
    });
    each_cell([&](std::size_t i) {
      put_scaled(w, sats[i].range_rate_mps - std::round(sats[i].range_rate_mps), 0.0001, 15);  // DF404
    });
  }
  return w.bytes();
}

}  // namespace gpsemu::rtk
