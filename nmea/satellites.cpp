// GSA (satellites used, DOPs) and GSV (satellites in view) formatters. Several sentences per
// epoch when the satellites do not fit one. Written straight into the epoch's text with the
// integer writers of text_append.hpp (no format strings: with fmt, GSV and GSA were 80% of a
// default epoch's instructions).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <string>
#include <string_view>

#include "nmea/fields.hpp"
#include "nmea/text_append.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {

constexpr int gsa_slots = 12;    // PRN fields per GSA
constexpr int gsv_per_sentence = 4;

/// A DOP field: two decimals, nothing when unknown.
void append_dop(std::string& out, double dop) {
  if (!std::isfinite(dop)) return;
  char text[24];
  out.append(text, fields::put_fixed(text, std::clamp(dop, 0.0, 99.99), 2, 100.0));
}

int in_view_count(const Fix& fix) { return std::clamp(fix.satellites_in_view, 0, static_cast<int>(max_satellites)); }

// The GSA fix type: 1 no fix, 2 for a 2-D fix, 3 otherwise.
int gsa_fix_type(const Fix& fix) {
  if (!fix.has_fix()) return 1;
  return fix.dimension == FixDimension::two_d ? 2 : 3;
}

/// Starts a sentence in `out`: "$" + talker + type. Returns where it starts.
std::size_t open_sentence(std::string& out, std::string_view talker, std::string_view type) {
  const std::size_t start = out.size();
  out += '$';
  out += talker;
  out += type;
  return start;
}

/// Ends the sentence that starts at `start`: "*hh\r\n".
void close_sentence_at(std::string& out, std::size_t start) {
  static constexpr char hex[] = "0123456789ABCDEF";
  const unsigned char sum = text::xor_bytes(out.data() + start + 1, out.data() + out.size());
  const char tail[] = {'*', hex[sum >> 4], hex[sum & 0x0f], '\r', '\n'};
  out.append(tail, sizeof tail);
}

}  // namespace

namespace {

/// The NMEA 4.1 systems in output order: talker, GSA system ID, first and second signal IDs.
struct NmeaSystem {
  std::string_view talker;
  char system_id;
  char signal_1;
  char signal_2;  // 0: no second signal (SBAS)
};
constexpr std::array<NmeaSystem, 5> nmea_systems{{
    {"GP", '1', '1', '6'},  // GPS (and SBAS, signal 1 only): L1 C/A, L2 CL
    {"GL", '2', '1', '3'},  // GLONASS: L1 OF, L2 OF
    {"GA", '3', '7', '2'},  // Galileo: E1, E5b
    {"GB", '4', '1', 'B'},  // BeiDou: B1I, B2I
    {"GQ", '5', '1', '6'},  // QZSS: L1 C/A, L2 CL
}};

std::size_t nmea_system_index(GnssSystem s) {
  switch (s) {
    case GnssSystem::gps:
    case GnssSystem::sbas: return 0;
    case GnssSystem::glonass: return 1;
    case GnssSystem::galileo: return 2;
    case GnssSystem::beidou: return 3;
    case GnssSystem::qzss: return 4;
  }
  return 0;
}

/// Which NMEA systems have satellites in view (bit i: nmea_systems[i]).
unsigned systems_in_view(const Fix& fix) {
  unsigned bits = 0;
  const int n = in_view_count(fix);
  for (int i = 0; i < n; ++i) bits |= 1u << nmea_system_index(fix.satellites[static_cast<std::size_t>(i)].system);
  return bits;
}

void append_gsa_of(const Fix& fix, const FormatOptions& options, std::string_view talker, int system, std::string& out) {
  const int type = gsa_fix_type(fix);
  std::array<int, max_satellites> prns{};
  int used = 0;
  if (fix.has_fix()) {
    const int n = in_view_count(fix);
    for (int i = 0; i < n; ++i) {
      const SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
      if (sat.used && (system < 0 || nmea_system_index(sat.system) == static_cast<std::size_t>(system))) {
        prns[static_cast<std::size_t>(used++)] = std::clamp(sat.prn, 0, 999);
      }
    }
  }
  // 12 PRN slots a sentence; one sentence even with none.
  for (int first = 0; first == 0 || first < used; first += gsa_slots) {
    const std::size_t start = open_sentence(out, talker, "GSA,A,");
    text::append_uint(out, static_cast<std::uint64_t>(type));
    for (int slot = 0; slot < gsa_slots; ++slot) {
      out += ',';
      if (first + slot < used) text::append_uint(out, static_cast<std::uint64_t>(prns[static_cast<std::size_t>(first + slot)]), 2);
    }
    out += ',';
    if (fix.has_fix()) {
      append_dop(out, fix.pdop);
      out += ',';
      append_dop(out, fix.hdop);
      out += ',';
      append_dop(out, fix.vdop);
    } else {
      out += "99.99,99.99,99.99";
    }
    if (options.version == NmeaVersion::v4_1) {
      out += ',';
      out += system < 0 ? '1' : nmea_systems[static_cast<std::size_t>(system)].system_id;
    }
    close_sentence_at(out, start);
  }
}

/// One GSV group: the satellites of NMEA system `system` on signal 1 or 2.
void append_gsv_group(const Fix& fix, const FormatOptions& options, std::size_t system, bool second_signal, std::string& out) {
  const NmeaSystem& sys = nmea_systems[system];
  const int n_all = in_view_count(fix);
  std::array<std::uint8_t, max_satellites> index{};
  int n = 0;
  for (int i = 0; i < n_all; ++i) {
    const SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
    if (nmea_system_index(sat.system) != system) continue;
    if (second_signal && sat.system == GnssSystem::sbas) continue;
    index[static_cast<std::size_t>(n++)] = static_cast<std::uint8_t>(i);
  }
  if (n == 0) return;
  const int total = (n + gsv_per_sentence - 1) / gsv_per_sentence;
  // Each sentence written into a buffer with the inline writers, then appended once (field by
  // field into the string, a GSV cost 470 instructions a satellite).
  constexpr std::size_t kMostBytes = 16 + gsv_per_sentence * 16 + 2 + 8;  // header, satellites, signal, "*hh\r\n" + 3
  for (int k = 0; k < total; ++k) {
    char sentence[kMostBytes];
    char* p = sentence;
    *p++ = '$';
    p = text::put_chars(p, sys.talker);
    p = text::put_chars(p, "GSV,");
    p = text::put_uint(p, static_cast<std::uint64_t>(total));
    *p++ = ',';
    p = text::put_uint(p, static_cast<std::uint64_t>(k + 1));
    *p++ = ',';
    p = text::put_uint(p, static_cast<std::uint64_t>(n), 2);
    for (int j = k * gsv_per_sentence; j < std::min(n, (k + 1) * gsv_per_sentence); ++j) {
      const SatelliteInView& sat = fix.satellites[index[static_cast<std::size_t>(j)]];
      *p++ = ',';
      p = text::put_uint(p, static_cast<std::uint64_t>(std::clamp(sat.prn, 0, 999)), 2);
      *p++ = ',';
      p = text::put_uint(p, static_cast<std::uint64_t>(std::clamp(sat.elevation_deg, 0, 90)), 2);
      *p++ = ',';
      p = text::put_uint(p, static_cast<std::uint64_t>(((sat.azimuth_deg % 360) + 360) % 360), 3);
      *p++ = ',';
      // The second signal is a few dB weaker than the first (L2/E5b/B2I against L1/E1/B1I).
      if (sat.snr_dbhz) p = text::put_uint(p, static_cast<std::uint64_t>(std::clamp(*sat.snr_dbhz - (second_signal ? 3 : 0), 0, 99)), 2);
    }
    if (options.version == NmeaVersion::v4_1) {
      *p++ = ',';
      *p++ = second_signal ? sys.signal_2 : sys.signal_1;
    }
    p = text::put_checksum(sentence, p);
    out.append(sentence, static_cast<std::size_t>(p - sentence));
  }
}

}  // namespace

void append_gsa(const Fix& fix, const FormatOptions& options, std::string& out) {
  // One GSA per system in view (u-blox's multi-GNSS output, talker GN); a single one otherwise.
  const unsigned bits = systems_in_view(fix);
  if (std::popcount(bits) <= 1) {
    const int system = bits == 0 ? -1 : std::countr_zero(bits);
    append_gsa_of(fix, options, options.talker, system, out);
    return;
  }
  for (std::size_t i = 0; i < nmea_systems.size(); ++i) {
    if (bits & (1u << i)) append_gsa_of(fix, options, options.talker, static_cast<int>(i), out);
  }
}

void append_gsv(const Fix& fix, const FormatOptions& options, std::string& out) {
  const unsigned bits = systems_in_view(fix);
  if (bits == 0) {
    const std::size_t start = open_sentence(out, options.talker == "GN" ? std::string_view("GP") : std::string_view(options.talker), "GSV,1,1,00");
    if (options.version == NmeaVersion::v4_1) out += ",1";
    close_sentence_at(out, start);
    return;
  }
  const bool second = options.gsv_second_signal && options.version == NmeaVersion::v4_1;
  for (std::size_t i = 0; i < nmea_systems.size(); ++i) {
    if (!(bits & (1u << i))) continue;
    append_gsv_group(fix, options, i, false, out);
    if (second) append_gsv_group(fix, options, i, true, out);
  }
}

std::string format_gsa(const Fix& fix, const FormatOptions& options) {
  std::string out;
  append_gsa(fix, options, out);
  return out;
}

std::string format_gsv(const Fix& fix, const FormatOptions& options) {
  std::string out;
  append_gsv(fix, options, out);
  return out;
}

}  // namespace gpsemu::nmea
