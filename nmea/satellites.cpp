// GSA (satellites used, DOPs) and GSV (satellites in view) formatters. Several sentences per
// epoch when the satellites do not fit one; no allocation beyond the returned text.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

#include "nmea/fields.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {

constexpr int gsa_slots = 12;    // PRN fields per GSA
constexpr int gsv_per_sentence = 4;

std::string dop_field(double dop) {
  if (!std::isfinite(dop)) return {};
  return fields::format_fixed(std::clamp(dop, 0.0, 99.99), 2, 100.0);
}

int in_view_count(const Fix& fix) { return std::clamp(fix.satellites_in_view, 0, static_cast<int>(max_satellites)); }

// The GSA fix type: 1 no fix, 2 for a 2-D fix, 3 otherwise.
int gsa_fix_type(const Fix& fix) {
  if (!fix.has_fix()) return 1;
  return fix.dimension == FixDimension::two_d ? 2 : 3;
}

}  // namespace

std::string format_gsa(const Fix& fix, const FormatOptions& options) {
  const std::string_view system_id = options.version == NmeaVersion::v4_1 ? ",1" : "";
  const int type = gsa_fix_type(fix);
  const std::string dops = fix.has_fix()
                               ? fmt::format("{},{},{}", dop_field(fix.pdop), dop_field(fix.hdop), dop_field(fix.vdop))
                               : std::string("99.99,99.99,99.99");
  std::string out;
  std::string prns;
  int in_sentence = 0;
  auto flush = [&] {
    for (int slot = in_sentence; slot < gsa_slots; ++slot) prns += ',';
    out += frame(fmt::format("{}GSA,A,{}{},{}{}", options.talker, type, prns, dops, system_id));
    prns.clear();
    in_sentence = 0;
  };
  if (fix.has_fix()) {
    const int n = in_view_count(fix);
    for (int i = 0; i < n; ++i) {
      const SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
      if (!sat.used) continue;
      prns += fmt::format(",{:02}", std::clamp(sat.prn, 0, 99));
      if (++in_sentence == gsa_slots) flush();
    }
  }
  if (in_sentence > 0 || out.empty()) flush();
  return out;
}

std::string format_gsv(const Fix& fix, const FormatOptions& options) {
  const std::string_view talker = options.talker == "GN" ? std::string_view("GP") : std::string_view(options.talker);
  const std::string_view signal_id = options.version == NmeaVersion::v4_1 ? ",1" : "";
  const int n = in_view_count(fix);
  if (n == 0) return frame(fmt::format("{}GSV,1,1,00{}", talker, signal_id));
  const int total = (n + gsv_per_sentence - 1) / gsv_per_sentence;
  std::string out;
  for (int k = 0; k < total; ++k) {
    std::string body = fmt::format("{}GSV,{},{},{:02}", talker, total, k + 1, n);
    for (int i = k * gsv_per_sentence; i < std::min(n, (k + 1) * gsv_per_sentence); ++i) {
      const SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
      const std::string snr = sat.snr_dbhz ? fmt::format("{:02}", std::clamp(*sat.snr_dbhz, 0, 99)) : std::string{};
      body += fmt::format(",{:02},{:02},{:03},{}", std::clamp(sat.prn, 0, 99), std::clamp(sat.elevation_deg, 0, 90),
                          ((sat.azimuth_deg % 360) + 360) % 360, snr);
    }
    body += signal_id;
    out += frame(body);
  }
  return out;
}

}  // namespace gpsemu::nmea
