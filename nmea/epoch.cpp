// One epoch's sentences in receiver order (table-driven dispatch by SentenceType), and the serial
// line budget of a sentence set, measured on the widest epoch the formatters can write.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string>

#include "nmea/epoch_fields.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {

using Formatter = std::string (*)(const Fix&, const FormatOptions&);

// Indexed by SentenceType (output order).
constexpr std::array<Formatter, all_sentence_types.size()> formatters = {
    format_rmc, format_vtg, format_gga, format_gsa, format_gsv, format_gll, format_gst, format_zda};

// The widest realistic epoch (see line_budget).
Fix widest_fix(int satellites_in_view, int satellites_used) {
  using namespace std::chrono;
  Fix fix;
  fix.time_utc = UtcTime{sys_days{year{2099} / December / 31}} + hours{23} + minutes{59} + seconds{59} +
                 milliseconds{999};
  fix.quality = FixQuality::rtk_float;
  fix.dimension = FixDimension::three_d;
  fix.lat_deg = -(89.0 + 59.99999 / 60.0);
  fix.lon_deg = -(179.0 + 59.99999 / 60.0);
  fix.alt_msl_m = 50000.0;
  fix.geoid_sep_m = -106.9;
  fix.speed_mps = 500.0;
  fix.course_deg_true = 359.99;
  fix.hdop = fix.vdop = fix.pdop = 99.99;
  fix.sigma_lat_m = fix.sigma_lon_m = fix.sigma_alt_m = fix.range_rms_m = 999.999;
  fix.satellites_in_view = std::clamp(satellites_in_view, 0, static_cast<int>(max_satellites));
  fix.satellites_used = std::clamp(satellites_used, 0, fix.satellites_in_view);
  for (int i = 0; i < fix.satellites_in_view; ++i) {
    fix.satellites[static_cast<std::size_t>(i)] = {32, 90, 359, 99, i < fix.satellites_used};
  }
  return fix;
}

}  // namespace

std::string format_sentences(SentenceType type, const Fix& fix, const FormatOptions& options) {
  return formatters[static_cast<std::size_t>(type)](fix, options);
}

void append_epoch(const Fix& fix, const FormatOptions& options, std::string& out) {
  // GGA and RMC share the time and position fields: formatted once, written straight into `out`.
  const bool with_gga = options.sentences.contains(SentenceType::gga);
  const bool with_rmc = options.sentences.contains(SentenceType::rmc);
  const EpochFields fields = with_gga || with_rmc ? epoch_fields(fix, options, with_rmc) : EpochFields{};
  options.sentences.for_each([&](SentenceType type) {
    switch (type) {
      case SentenceType::gga: append_gga(fix, options, fields, out); break;
      case SentenceType::rmc: append_rmc(fix, options, fields, out); break;
      case SentenceType::gsa: append_gsa(fix, options, out); break;
      case SentenceType::gsv: append_gsv(fix, options, out); break;
      default: out += format_sentences(type, fix, options); break;
    }
  });
}

LineBudget line_budget(const FormatOptions& options, int satellites_in_view, int satellites_used, double rate_hz) {
  std::string epoch;
  append_epoch(widest_fix(satellites_in_view, satellites_used), options, epoch);
  LineBudget budget;
  budget.bytes_per_epoch = epoch.size();
  budget.bytes_per_second = static_cast<double>(epoch.size()) * rate_hz;
  budget.min_baud = 10.0 * budget.bytes_per_second;
  return budget;
}

int smallest_standard_baud(const LineBudget& budget) {
  for (const int baud : {4800, 9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600}) {
    if (budget.fits(baud)) return baud;
  }
  return 0;
}

}  // namespace gpsemu::nmea
