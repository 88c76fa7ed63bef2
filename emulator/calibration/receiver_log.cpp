#include "emulator/calibration/receiver_log.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::calibration {

ReceiverLog read_receiver_log(std::string_view bytes) {
  ReceiverLog log;
  nmea::StreamReader reader;
  std::vector<nmea::Sentence> sentences = reader.feed(bytes);
  if (auto last = reader.finish()) sentences.push_back(std::move(*last));
  log.counts.stream = reader.stats();

  std::map<int, std::size_t> decimals;  // minute decimals -> fixes
  double first_tod_s = 0.0, prev_s = -std::numeric_limits<double>::infinity(), day_offset_s = 0.0;
  double prev_tod_s = 0.0;
  for (const nmea::Sentence& s : sentences) {
    if (s.type != "GGA") continue;
    ++log.counts.gga;
    const auto gga = nmea::parse_gga(s);
    if (!gga) {
      ++log.counts.gga_malformed;
      continue;
    }
    if (gga->quality == nmea::FixQuality::none || !gga->lat_deg || !gga->lon_deg ||
        !gga->alt_msl_m || !gga->time_of_day) {
      ++log.counts.gga_no_fix;
      continue;
    }
    const double tod_s = static_cast<double>(gga->time_of_day->count()) / 1000.0;
    if (!log.fixes.empty() && tod_s < prev_tod_s - 43200.0) day_offset_s += 86400.0;  // midnight
    prev_tod_s = tod_s;
    if (log.fixes.empty()) first_tod_s = tod_s;
    const double t = tod_s + day_offset_s - first_tod_s;
    if (t <= prev_s) {
      ++log.counts.repeated_time;
      continue;
    }
    prev_s = t;
    log.fixes.push_back({t, {*gga->lat_deg, *gga->lon_deg, *gga->alt_msl_m}, gga->hdop});
    ++decimals[gga->minute_decimals];
  }
  std::size_t best = 0;
  for (const auto& [d, n] : decimals) {
    if (n > best) best = n, log.minute_decimals = d;
  }
  return log;
}

ReceiverLog read_receiver_log_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot read receiver log '{}'", path));
  std::ostringstream text;
  text << in.rdbuf();
  return read_receiver_log(text.str());
}

double snap_rate_hz(double rate_hz) {
  static const std::vector<double> rates = [] {
    std::vector<double> r{0.1, 0.2, 0.25, 0.5};
    for (int i = 1; i <= 50; ++i) r.push_back(i);
    return r;
  }();
  double best = 1.0, best_err = std::numeric_limits<double>::infinity();
  for (double r : rates) {
    const double err = std::abs(std::log(rate_hz / r));
    if (err < best_err) best_err = err, best = r;
  }
  return best;
}

EnuSeries to_enu_series(ReceiverLog& log) {
  constexpr std::size_t kMinFixes = 16;
  if (log.fixes.size() < kMinFixes) {
    throw std::invalid_argument(fmt::format(
        "the log has {} usable fixes; calibration needs at least {} (GGA with a fix)",
        log.fixes.size(), kMinFixes));
  }
  std::vector<double> intervals;
  for (std::size_t i = 1; i < log.fixes.size(); ++i)
    intervals.push_back(log.fixes[i].time_s - log.fixes[i - 1].time_s);
  std::nth_element(intervals.begin(), intervals.begin() + intervals.size() / 2, intervals.end());
  EnuSeries out;
  out.rate_hz = snap_rate_hz(1.0 / intervals[intervals.size() / 2]);
  out.minute_decimals = log.minute_decimals;

  // Mean position: latitude, longitude and altitude averaged (the spread is metres, so the
  // arithmetic mean of the angles is the centre to far better than a millimetre).
  Geodetic c{0.0, 0.0, 0.0};
  const double lon0 = log.fixes.front().position.lon_deg;
  for (const LogFix& f : log.fixes) {
    c.lat_deg += f.position.lat_deg;
    c.lon_deg += wrap_lon_deg(f.position.lon_deg - lon0);  // safe across the antimeridian
    c.alt_m += f.position.alt_m;
  }
  const double n = static_cast<double>(log.fixes.size());
  out.centre = {c.lat_deg / n, wrap_lon_deg(lon0 + c.lon_deg / n), c.alt_m / n};

  // Every grid epoch from the first fix to the last gets a sample: refuse a span (a log whose times
  // jump ahead by days, or a corrupt one) that would take gigabytes.
  constexpr double kMaxEpochs = 1e7;
  const double span_epochs = log.fixes.back().time_s * out.rate_hz;
  if (!(span_epochs < kMaxEpochs)) {
    throw std::invalid_argument(fmt::format(
        "the log's fixes span {:.0f} s, {:.0f} epochs at {} Hz: calibration takes at most {:.0f} epochs of one "
        "continuous recording", log.fixes.back().time_s, span_epochs, out.rate_hz, kMaxEpochs));
  }
  const auto last = static_cast<std::size_t>(std::llround(span_epochs));
  for (auto& a : out.axis_m) a.assign(last + 1, std::numeric_limits<double>::quiet_NaN());
  const LocalFrame frame(out.centre);
  std::size_t filled = 0;
  for (const LogFix& f : log.fixes) {
    const auto k = static_cast<std::size_t>(std::llround(f.time_s * out.rate_hz));
    if (!std::isnan(out.axis_m[0][k])) {
      ++log.counts.repeated_time;
      continue;
    }
    const Enu e = frame.to_enu(f.position);
    out.axis_m[0][k] = e.east_m;
    out.axis_m[1][k] = e.north_m;
    out.axis_m[2][k] = e.up_m;
    ++filled;
  }
  log.counts.missing_epochs = out.size() - filled;
  return out;
}

}  // namespace gpsemu::calibration
