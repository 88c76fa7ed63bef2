// One epoch's sentences in receiver order (table-driven dispatch by SentenceType).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "nmea/epoch_fields.hpp"
#include "nmea/heading.hpp"
#include "nmea/sentences.hpp"
#include "nmea/text_append.hpp"

namespace gpsemu::nmea {
namespace {

using Formatter = std::string (*)(const Fix&, const FormatOptions&);

// Indexed by SentenceType (output order).
constexpr std::array<Formatter, all_sentence_types.size()> formatters = {
    format_rmc, format_vtg, format_gga, format_gsa, format_gsv, format_gll, format_gst, format_zda, format_hdt, format_ths};

}  // namespace

std::string format_sentences(SentenceType type, const Fix& fix, const FormatOptions& options) {
  return formatters[static_cast<std::size_t>(type)](fix, options);
}

namespace {

bool same_satellite(const SatelliteInView& a, const SatelliteInView& b) {
  return a.prn == b.prn && a.elevation_deg == b.elevation_deg && a.azimuth_deg == b.azimuth_deg &&
         a.snr_dbhz == b.snr_dbhz && a.used == b.used && a.system == b.system && a.sv_id == b.sv_id;
}

/// What GSA writes of a satellite: its number and system, and whether it is used.
bool same_in_gsa(const SatelliteInView& a, const SatelliteInView& b) {
  return a.prn == b.prn && a.used == b.used && a.system == b.system;
}

/// A DOP as GSA writes it (satellites.cpp: clamped to 0..99.99, two decimals; -1 when not
/// finite): the memo keeps these, so a DOP that changes below the printed digits keeps the text.
double dop_as_written(double dop) {
  if (!std::isfinite(dop)) return -1.0;
  return static_cast<double>(text::round_half_away(std::clamp(dop, 0.0, 99.99) * 100.0)) / 100.0;
}

/// Brings `memo` up to date with `fix`: what is still valid stays, the rest is formatted again.
void refresh(const Fix& fix, const FormatOptions& options, SatelliteTextMemo& memo) {
  const int n = std::clamp(fix.satellites_in_view, 0, static_cast<int>(max_satellites));
  const auto first = fix.satellites.cbegin();
  // Equal bytes are equal satellites (plain integers and flags; the padding between them only
  // ever makes equal satellites look different, and then the fields are compared): one memcmp of
  // ~700 bytes an epoch in place of seven fields of every satellite (600 instructions an epoch).
  static_assert(std::is_trivially_copyable_v<SatelliteInView>);
  const bool same_bytes = memo.in_view == n && std::memcmp(fix.satellites.data(), memo.satellites.data(),
                                                           static_cast<std::size_t>(n) * sizeof(SatelliteInView)) == 0;
  if (!same_bytes) {
    const bool same_count = memo.in_view == n;
    if (!same_count || !std::equal(first, first + n, memo.satellites.cbegin(), same_satellite)) {
      // GSA lists the used ones' numbers by system only: an azimuth, elevation or C/N0 keeps its text.
      if (!same_count || !std::equal(first, first + n, memo.satellites.cbegin(), same_in_gsa)) memo.gsa_valid = false;
      memo.gsv_valid = false;
    }
    memo.in_view = n;
    std::copy_n(first, n, memo.satellites.begin());  // the bytes too: the next epoch's memcmp
  }
  const double pdop = dop_as_written(fix.pdop), hdop = dop_as_written(fix.hdop), vdop = dop_as_written(fix.vdop);
  if (memo.quality != fix.quality || memo.dimension != fix.dimension || memo.pdop != pdop || memo.hdop != hdop ||
      memo.vdop != vdop) {
    memo.gsa_valid = false;
    memo.quality = fix.quality;
    memo.dimension = fix.dimension;
    memo.pdop = pdop;
    memo.hdop = hdop;
    memo.vdop = vdop;
  }
  if (!memo.gsv_valid && options.sentences.contains(SentenceType::gsv)) {
    memo.gsv.clear();
    append_gsv(fix, options, memo.gsv);
    memo.gsv_valid = true;
  }
  if (!memo.gsa_valid && options.sentences.contains(SentenceType::gsa)) {
    memo.gsa.clear();
    append_gsa(fix, options, memo.gsa);
    memo.gsa_valid = true;
  }
}

void append_epoch_with(const Fix& fix, const FormatOptions& options, std::string& out, SatelliteTextMemo* memo) {
  // Without GSA and GSV there is no satellite text to keep (comparing the satellites would cost
  // a thousand instructions an epoch for nothing).
  if (memo && (options.sentences.contains(SentenceType::gsa) || options.sentences.contains(SentenceType::gsv))) {
    refresh(fix, options, *memo);
  }
  // GGA, RMC and GLL share the time and position fields: formatted once, written straight into `out`.
  const bool with_rmc = options.sentences.contains(SentenceType::rmc);
  const bool shared = with_rmc || options.sentences.contains(SentenceType::gga) ||
                      options.sentences.contains(SentenceType::gll);
  const EpochFields fields = shared ? epoch_fields(fix, options, with_rmc) : EpochFields{};
  options.sentences.for_each([&](SentenceType type) {
    switch (type) {
      case SentenceType::gga: append_gga(fix, options, fields, out); break;
      case SentenceType::rmc: append_rmc(fix, options, fields, out); break;
      case SentenceType::vtg: append_vtg(fix, options, out); break;
      case SentenceType::gll: append_gll(fix, options, fields, out); break;
      case SentenceType::gsa: memo ? void(out += memo->gsa) : append_gsa(fix, options, out); break;
      case SentenceType::gsv: memo ? void(out += memo->gsv) : append_gsv(fix, options, out); break;
      default: out += format_sentences(type, fix, options); break;
    }
  });
}

}  // namespace

void append_epoch(const Fix& fix, const FormatOptions& options, std::string& out) {
  append_epoch_with(fix, options, out, nullptr);
}

void append_epoch(const Fix& fix, const FormatOptions& options, std::string& out, SatelliteTextMemo& memo) {
  append_epoch_with(fix, options, out, &memo);
}

}  // namespace gpsemu::nmea
