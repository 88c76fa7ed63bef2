// Satellite messages (see nav_sat.hpp).
#include "emulator/ubx/nav_sat.hpp"

#include <algorithm>
#include <array>

#include "emulator/ubx/layouts.hpp"
#include "emulator/ubx/nav.hpp"

namespace gpsemu::ubx {
namespace {

using nmea::FixQuality;
using nmea::GnssSystem;

constexpr std::uint8_t kGps = 0, kSbas = 1, kGalileo = 2, kBeidou = 3, kQzss = 5, kGlonass = 6;

int satellite_count(const nmea::Fix& fix) {
  return std::clamp(fix.satellites_in_view, 0, static_cast<int>(nmea::max_satellites));
}

bool differential(const nmea::Fix& fix) {
  return fix.quality == FixQuality::dgps || fix.quality == FixQuality::rtk_float || fix.quality == FixQuality::rtk_fixed;
}
bool carrier(const nmea::Fix& fix) {
  return fix.quality == FixQuality::rtk_float || fix.quality == FixQuality::rtk_fixed;
}

/// The second band of a system on a dual-band receiver: its sigId and how much weaker (dB).
struct SecondBand {
  bool has = false;
  std::uint8_t sig_id = 0;
  int cno_offset_db = 0;
};
SecondBand second_band(std::uint8_t gnss_id, std::uint8_t sv_id) {
  switch (gnss_id) {
    case kGps: return {true, 3, -4};      // L2 CL
    case kGalileo: return {true, 5, -1};  // E5b I
    case kBeidou: return {true, static_cast<std::uint8_t>(sv_id <= 5 || sv_id >= 59 ? 3 : 2), -2};  // B2I D2 (GEO), D1
    case kQzss: return {true, 5, -4};     // L2 CL
    case kGlonass: return {true, 2, -4};  // L2 OF
    default: return {};                   // SBAS: L1 only
  }
}
/// sigId of the L1 signal: BeiDou GEO satellites send D2 (sigId 1), the others 0 (L1 C/A, E1 C, B1I D1, L1 OF).
std::uint8_t first_band_sig_id(std::uint8_t gnss_id, std::uint8_t sv_id) {
  return gnss_id == kBeidou && (sv_id <= 5 || sv_id >= 59) ? 1 : 0;
}

void append_signal(std::string& p, const nmea::Fix& fix, const nmea::SatelliteInView& sat, UbxSatId id,
                std::uint8_t sig_id, int cno_dbhz, bool dual) {
  const bool used = sat.used && fix.has_fix();
  const bool diff = used && differential(fix);
  const std::uint32_t freq_id =
      id.gnss_id == kGlonass ? static_cast<std::uint32_t>(glonass_frequency_channel(id.sv_id) + 7) : 0;
  // corrSource: 1 SBAS, 4 RTCM3 OSR; ionoModel: 1 Klobuchar (GPS), 2 SBAS, 8 dual frequency.
  const std::uint32_t corr_source = !diff ? 0 : carrier(fix) ? 4 : 1;
  const std::uint32_t iono_model = !used ? 0 : dual ? 8 : fix.quality == FixQuality::dgps ? 2 : 1;
  std::uint32_t flags = 0x01;                      // health: healthy
  if (used) flags |= 0x08 | 0x20;                  // prUsed, doUsed
  if (used && carrier(fix)) flags |= 0x10 | 0x80;  // crUsed, crCorrUsed
  if (diff) flags |= 0x40 | 0x100;                 // prCorrUsed, doCorrUsed
  PayloadWriter<layout::nav_sig_block> w;
  w.set<"gnssId">(id.gnss_id);
  w.set<"svId">(id.sv_id);
  w.set<"sigId">(sig_id);
  w.set<"freqId">(freq_id);
  w.set<"prRes">(0);
  w.set<"cno">(std::clamp(cno_dbhz, 0, 255));
  w.set<"qualityInd">(used ? 7u : 4u);  // code and carrier locked / code locked
  w.set<"corrSource">(corr_source);
  w.set<"ionoModel">(iono_model);
  w.set<"sigFlags">(flags);
  p += w.bytes();
}

}  // namespace

UbxSatId ubx_sat_id(const nmea::SatelliteInView& sat) {
  if (sat.sv_id > 0) return {static_cast<std::uint8_t>(sat.system), static_cast<std::uint8_t>(std::min(sat.sv_id, 255))};
  if (sat.prn >= 33 && sat.prn <= 64) return {kSbas, static_cast<std::uint8_t>(sat.prn + 87)};
  if (sat.prn >= 65 && sat.prn <= 96) return {kGlonass, static_cast<std::uint8_t>(sat.prn - 64)};
  return {static_cast<std::uint8_t>(sat.system), static_cast<std::uint8_t>(std::clamp(sat.prn, 0, 255))};
}

std::uint8_t svinfo_svid(UbxSatId id) {
  const int sv = id.sv_id;
  switch (id.gnss_id) {
    case kGps: return sv >= 1 && sv <= 32 ? static_cast<std::uint8_t>(sv) : 255;
    case kSbas: return sv >= 120 && sv <= 158 ? static_cast<std::uint8_t>(sv) : 255;
    case kGalileo: return sv >= 1 && sv <= 36 ? static_cast<std::uint8_t>(sv + 210) : 255;
    case kBeidou:
      if (sv >= 1 && sv <= 5) return static_cast<std::uint8_t>(sv + 158);
      return sv >= 6 && sv <= 37 ? static_cast<std::uint8_t>(sv + 27) : 255;
    case kQzss: return sv >= 1 && sv <= 10 ? static_cast<std::uint8_t>(sv + 192) : 255;
    case kGlonass: return sv >= 1 && sv <= 32 ? static_cast<std::uint8_t>(sv + 64) : 255;
    default: return 255;
  }
}

int glonass_frequency_channel(int slot) {
  // The GLONASS constellation's slot -> frequency channel plan (antipodal slots share a channel).
  constexpr std::array<int, 24> channel = {1, -4, 5, 6, 1, -4, 5, 6, -2, -7, 0, -1,
                                           -2, -7, 0, -1, 4, -3, 3, 2, 4, -3, 3, 2};
  return slot >= 1 && slot <= 24 ? channel[static_cast<std::size_t>(slot - 1)] : 0;
}

std::string nav_sat(const nmea::Fix& fix) {
  const int count = satellite_count(fix);
  const bool diff = differential(fix);
  PayloadWriter<layout::nav_sat> header;
  header.set<"iTOW">(gps_time(fix).tow_ms);
  header.set<"version">(1);
  header.set<"numSvs">(count);
  std::string p = std::move(header).bytes();
  p.reserve(8 + 12 * static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const nmea::SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
    const UbxSatId id = ubx_sat_id(sat);
    const bool tracked = sat.snr_dbhz.has_value();
    const bool used = sat.used && fix.has_fix();
    // qualityInd: 7 code and carrier locked (used), 4 code locked, 1 searching.
    const std::uint32_t quality = used ? 7 : tracked ? 4 : 1;
    std::uint32_t flags = quality | (used ? 0x08u : 0u) | 0x10u;  // health 1: healthy
    if (used && diff) flags |= 0x40u;                             // diffCorr
    if (used) flags |= 0x100u | 0x800u;                           // orbitSource ephemeris, ephAvail
    PayloadWriter<layout::nav_sat_block> w;
    w.set<"gnssId">(id.gnss_id);
    w.set<"svId">(id.sv_id);
    w.set<"cno">(sat.snr_dbhz.value_or(0));
    w.set<"elev">(sat.elevation_deg);
    w.set<"azim">(sat.azimuth_deg);
    w.set<"prRes">(0);
    w.set<"flags">(flags);
    p += w.bytes();
  }
  return p;
}

std::string nav_svinfo(const nmea::Fix& fix) {
  const int count = satellite_count(fix);
  const bool diff = differential(fix);
  PayloadWriter<layout::nav_svinfo> header;
  header.set<"iTOW">(gps_time(fix).tow_ms);
  header.set<"numCh">(count);
  header.set<"globalFlags">(4);  // chipGen 4, u-blox 8
  std::string p = std::move(header).bytes();
  p.reserve(8 + 12 * static_cast<std::size_t>(count));
  int channel = 0;
  for (int i = 0; i < count; ++i) {
    const nmea::SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
    const bool tracked = sat.snr_dbhz.has_value();
    const bool used = sat.used && fix.has_fix();
    // flags: svUsed, diffCorr, orbitAvail, orbitEph; quality: 7 carrier locked, 4 code locked, 1 searching.
    std::uint32_t flags = 0;
    if (used) flags |= 0x01 | 0x04 | 0x08;
    if (used && diff) flags |= 0x02;
    if (tracked && !used) flags |= 0x04;
    PayloadWriter<layout::nav_svinfo_block> w;
    w.set<"chn">(tracked ? channel++ : 255);  // 255 without a channel
    w.set<"svid">(svinfo_svid(ubx_sat_id(sat)));
    w.set<"flags">(flags);
    w.set<"quality">(used ? 7u : tracked ? 4u : 1u);
    w.set<"cno">(sat.snr_dbhz.value_or(0));
    w.set<"elev">(sat.elevation_deg);
    w.set<"azim">(sat.azimuth_deg);
    w.set<"prRes">(0);
    p += w.bytes();
  }
  return p;
}

int signal_count(const nmea::Fix& fix, ReceiverModel model) {
  int n = 0;
  for (int i = 0; i < satellite_count(fix); ++i) {
    const nmea::SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
    if (!sat.snr_dbhz) continue;
    const UbxSatId id = ubx_sat_id(sat);
    n += 1 + (dual_band(model) && second_band(id.gnss_id, id.sv_id).has ? 1 : 0);
  }
  return n;
}

std::string nav_sig(const nmea::Fix& fix, ReceiverModel model) {
  const int signals = signal_count(fix, model);
  const bool dual = dual_band(model);
  PayloadWriter<layout::nav_sig> header;
  header.set<"iTOW">(gps_time(fix).tow_ms);
  header.set<"version">(0);
  header.set<"numSigs">(signals);
  std::string p = std::move(header).bytes();
  p.reserve(8 + 16 * static_cast<std::size_t>(signals));
  for (int i = 0; i < satellite_count(fix); ++i) {
    const nmea::SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
    if (!sat.snr_dbhz) continue;
    const UbxSatId id = ubx_sat_id(sat);
    const SecondBand second = second_band(id.gnss_id, id.sv_id);
    const bool two = dual && second.has;
    append_signal(p, fix, sat, id, first_band_sig_id(id.gnss_id, id.sv_id), *sat.snr_dbhz, two);
    if (two) append_signal(p, fix, sat, id, second.sig_id, *sat.snr_dbhz + second.cno_offset_db, true);
  }
  return p;
}

}  // namespace gpsemu::ubx
