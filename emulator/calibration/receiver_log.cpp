#include "emulator/calibration/receiver_log.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::calibration {

namespace {

// A VTG's speed over ground: field 6 (km/h), else field 4 (knots); nullopt when neither parses.
std::optional<double> vtg_speed_mps(const nmea::Sentence& s) {
  const auto number = [&](std::size_t i) -> std::optional<double> {
    if (s.fields.size() <= i || s.fields[i].empty()) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(s.fields[i].c_str(), &end);
    if (end != s.fields[i].c_str() + s.fields[i].size() || !std::isfinite(v) || v < 0.0) return std::nullopt;
    return v;
  };
  if (const auto kmh = number(6)) return *kmh / 3.6;
  if (const auto knots = number(4)) return *knots * 1852.0 / 3600.0;
  return std::nullopt;
}

}  // namespace

void ReceiverLogReader::feed(std::string_view bytes) {
  for (const nmea::Sentence& s : stream_.feed(bytes)) take(s);
}

void ReceiverLogReader::take(const nmea::Sentence& s) {
  const double now_s = log_.fixes.empty() ? 0.0 : log_.fixes.back().time_s;
  if (s.type == "RMC") {
    const auto rmc = nmea::parse_rmc(s);
    if (rmc && rmc->status_active && rmc->speed_mps) {
      log_.speeds.push_back({now_s, static_cast<float>(*rmc->speed_mps)});
      ++log_.counts.speed_reports;
    }
    return;
  }
  if (s.type == "VTG") {
    if (const auto v = vtg_speed_mps(s)) {
      vtg_speeds_.push_back({now_s, static_cast<float>(*v)});
      ++log_.counts.speed_reports;
    }
    return;
  }
  if (s.type != "GGA") return;
  ++log_.counts.gga;
  const auto gga = nmea::parse_gga(s);
  if (!gga) {
    ++log_.counts.gga_malformed;
    return;
  }
  if (gga->quality == nmea::FixQuality::none || !gga->lat_deg || !gga->lon_deg || !gga->alt_msl_m ||
      !gga->time_of_day) {
    ++log_.counts.gga_no_fix;
    return;
  }
  const double tod_s = static_cast<double>(gga->time_of_day->count()) / 1000.0;
  if (!log_.fixes.empty() && tod_s < prev_tod_s_ - 43200.0) day_offset_s_ += 86400.0;  // midnight
  prev_tod_s_ = tod_s;
  if (log_.fixes.empty()) first_tod_s_ = tod_s;
  const double t = tod_s + day_offset_s_ - first_tod_s_;
  if (!log_.fixes.empty() && t <= prev_s_) {
    ++log_.counts.repeated_time;
    return;
  }
  prev_s_ = t;
  log_.fixes.push_back({t, {*gga->lat_deg, *gga->lon_deg, *gga->alt_msl_m}, gga->hdop});
  ++decimals_[static_cast<std::size_t>(std::clamp(gga->minute_decimals, 0, 9))];
  const std::string& alt = s.fields[8];  // parse_gga read it, so the field exists
  const auto dot = alt.find('.');
  ++alt_decimals_[dot == std::string::npos ? 0 : std::min<std::size_t>(alt.size() - dot - 1, 9)];
}

ReceiverLog ReceiverLogReader::finish() {
  if (auto last = stream_.finish()) take(*last);
  log_.counts.stream = stream_.stats();
  if (log_.speeds.empty()) log_.speeds = std::move(vtg_speeds_);
  log_.counts.speed_reports = log_.speeds.size();
  std::size_t best = 0;
  for (std::size_t d = 0; d < decimals_.size(); ++d)
    if (decimals_[d] > best) best = decimals_[d], log_.minute_decimals = static_cast<int>(d);
  best = 0;
  for (std::size_t d = 0; d < alt_decimals_.size(); ++d)
    if (alt_decimals_[d] > best) best = alt_decimals_[d], log_.alt_decimals = static_cast<int>(d);
  log_.fixes.shrink_to_fit();
  return std::move(log_);
}

ReceiverLog read_receiver_log(std::string_view bytes) {
  ReceiverLogReader reader;
  reader.feed(bytes);
  return reader.finish();
}

ReceiverLog read_receiver_log_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot read receiver log '{}'", path));
  ReceiverLogReader reader;
  std::string chunk(1 << 20, '\0');
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    if (in.gcount() > 0) reader.feed(std::string_view(chunk.data(), static_cast<std::size_t>(in.gcount())));
  }
  if (in.bad()) throw std::runtime_error(fmt::format("cannot read receiver log '{}'", path));
  return reader.finish();
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

EnuSeries to_enu_series(ReceiverLog& log, std::size_t max_epochs, std::string_view why_limit) {
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
  out.alt_decimals = log.alt_decimals;

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
  // jump ahead by days, or a corrupt one) that would take more memory than there is.
  const double span_epochs = log.fixes.back().time_s * out.rate_hz;
  const auto max_epochs_d = static_cast<double>(std::min(max_epochs, kMaxCalibrationEpochs));
  if (!(span_epochs < max_epochs_d)) {
    throw std::invalid_argument(fmt::format(
        "the log's fixes span {:.0f} s, {:.0f} epochs at {} Hz: calibration takes at most {:.0f} epochs of one "
        "continuous recording{}", log.fixes.back().time_s, span_epochs, out.rate_hz, max_epochs_d,
        why_limit.empty() ? std::string() : fmt::format(" ({})", why_limit)));
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
