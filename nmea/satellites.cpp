// GSA (satellites used, DOPs) and GSV (satellites in view) formatters. Several sentences per
// epoch when the satellites do not fit one. Written straight into the epoch's text with the
// integer writers of text_append.hpp (no format strings: with fmt, GSV and GSA were 80% of a
// default epoch's instructions).
#include <algorithm>
#include <array>
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

void append_gsa(const Fix& fix, const FormatOptions& options, std::string& out) {
  const std::string_view system_id = options.version == NmeaVersion::v4_1 ? ",1" : "";
  const int type = gsa_fix_type(fix);
  std::array<int, max_satellites> prns{};
  int used = 0;
  if (fix.has_fix()) {
    const int n = in_view_count(fix);
    for (int i = 0; i < n; ++i) {
      const SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
      if (sat.used) prns[static_cast<std::size_t>(used++)] = std::clamp(sat.prn, 0, 99);
    }
  }
  // 12 PRN slots a sentence; one sentence even with none.
  for (int first = 0; first == 0 || first < used; first += gsa_slots) {
    const std::size_t start = open_sentence(out, options.talker, "GSA,A,");
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
    out += system_id;
    close_sentence_at(out, start);
  }
}

void append_gsv(const Fix& fix, const FormatOptions& options, std::string& out) {
  const std::string_view talker = options.talker == "GN" ? std::string_view("GP") : std::string_view(options.talker);
  const std::string_view signal_id = options.version == NmeaVersion::v4_1 ? ",1" : "";
  const int n = in_view_count(fix);
  if (n == 0) {
    const std::size_t start = open_sentence(out, talker, "GSV,1,1,00");
    out += signal_id;
    close_sentence_at(out, start);
    return;
  }
  const int total = (n + gsv_per_sentence - 1) / gsv_per_sentence;
  for (int k = 0; k < total; ++k) {
    const std::size_t start = open_sentence(out, talker, "GSV,");
    text::append_uint(out, static_cast<std::uint64_t>(total));
    out += ',';
    text::append_uint(out, static_cast<std::uint64_t>(k + 1));
    out += ',';
    text::append_uint(out, static_cast<std::uint64_t>(n), 2);
    for (int i = k * gsv_per_sentence; i < std::min(n, (k + 1) * gsv_per_sentence); ++i) {
      const SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
      out += ',';
      text::append_uint(out, static_cast<std::uint64_t>(std::clamp(sat.prn, 0, 99)), 2);
      out += ',';
      text::append_uint(out, static_cast<std::uint64_t>(std::clamp(sat.elevation_deg, 0, 90)), 2);
      out += ',';
      text::append_uint(out, static_cast<std::uint64_t>(((sat.azimuth_deg % 360) + 360) % 360), 3);
      out += ',';
      if (sat.snr_dbhz) text::append_uint(out, static_cast<std::uint64_t>(std::clamp(*sat.snr_dbhz, 0, 99)), 2);
    }
    out += signal_id;
    close_sentence_at(out, start);
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
