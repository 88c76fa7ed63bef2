#include "emulator/calibration/motion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace gpsemu::calibration {
namespace {

bool present(const EnuSeries& s, std::size_t k) { return !std::isnan(s.axis_m[0][k]) && !std::isnan(s.axis_m[1][k]); }

// Mean east, north over indices [from, to) that have a fix; false when none.
bool mean_over(const EnuSeries& s, std::size_t from, std::size_t to, double& e, double& n) {
  double se = 0.0, sn = 0.0, count = 0.0;
  for (std::size_t k = from; k < to; ++k)
    if (present(s, k)) se += s.axis_m[0][k], sn += s.axis_m[1][k], count += 1.0;
  if (count == 0.0) return false;
  e = se / count, n = sn / count;
  return true;
}

// The local quadratic least-squares fit of x over [lo, hi) evaluated at `at` (NaN skipped).
double local_quadratic(const std::vector<double>& x, std::size_t lo, std::size_t hi, std::size_t at) {
  // Centred abscissa for conditioning; normal equations of 1, u, u^2.
  const double c = 0.5 * static_cast<double>(lo + hi - 1);
  std::array<double, 5> su{};  // sum u^0..u^4
  std::array<double, 3> sy{};  // sum y u^0..u^2
  for (std::size_t k = lo; k < hi; ++k) {
    if (std::isnan(x[k])) continue;
    const double u = static_cast<double>(k) - c;
    double p = 1.0;
    for (int j = 0; j < 5; ++j) {
      su[j] += p;
      if (j < 3) sy[j] += p * x[k];
      p *= u;
    }
  }
  const double a00 = su[0], a01 = su[1], a02 = su[2], a11 = su[2], a12 = su[3], a22 = su[4];
  const double det = a00 * (a11 * a22 - a12 * a12) - a01 * (a01 * a22 - a12 * a02) + a02 * (a01 * a12 - a11 * a02);
  if (std::abs(det) < 1e-12 * std::max(1.0, a22 * a22 * a00)) return su[0] > 0.0 ? sy[0] / su[0] : 0.0;
  // Cramer's rule.
  const double b0 = sy[0], b1 = sy[1], b2 = sy[2];
  const double c0 = (b0 * (a11 * a22 - a12 * a12) - a01 * (b1 * a22 - a12 * b2) + a02 * (b1 * a12 - a11 * b2)) / det;
  const double c1 = (a00 * (b1 * a22 - a12 * b2) - b0 * (a01 * a22 - a12 * a02) + a02 * (a01 * b2 - b1 * a02)) / det;
  const double c2 = (a00 * (a11 * b2 - b1 * a12) - a01 * (a01 * b2 - b1 * a02) + b0 * (a01 * a12 - a11 * a02)) / det;
  const double u = static_cast<double>(at) - c;
  return c0 + c1 * u + c2 * u * u;
}

// Standard deviation of x about its least-squares line in the sample index (NaN skipped).
double sd_about_line(const std::vector<double>& x) {
  double n = 0, su = 0, sx = 0, suu = 0, sux = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (std::isnan(x[k])) continue;
    const double u = static_cast<double>(k);
    n += 1, su += u, sx += x[k], suu += u * u, sux += u * x[k];
  }
  if (n < 3) return 0.0;
  const double var_u = suu / n - (su / n) * (su / n);
  const double slope = var_u > 0.0 ? (sux / n - (su / n) * (sx / n)) / var_u : 0.0;
  double sum2 = 0;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (!std::isnan(x[k])) {
      const double r = x[k] - sx / n - slope * (static_cast<double>(k) - su / n);
      sum2 += r * r;
    }
  return std::sqrt(sum2 / n);
}

// Standard deviation of x's first differences (pairs with a NaN skipped).
double first_difference_sd(const std::vector<double>& x) {
  double n = 0, s = 0, s2 = 0;
  for (std::size_t k = 1; k < x.size(); ++k)
    if (!std::isnan(x[k]) && !std::isnan(x[k - 1])) {
      const double d = x[k] - x[k - 1];
      n += 1, s += d, s2 += d * d;
    }
  return n > 1 ? std::sqrt(std::max(0.0, s2 / n - (s / n) * (s / n))) : 0.0;
}

}  // namespace

std::string MotionCheck::describe() const {
  std::string out = fmt::format("net displacement {:.1f} m, sustained speed {:.2f} m/s (median over {:.0f} s windows)",
                                displacement_m, speed_mps, window_s);
  if (reported_speed_mps)
    out += fmt::format(", reported speed over ground {:.3f} m/s (median of {:.0f} s means, {} reports), smoothed "
                       "track spanning {:.1f} m (its tenths' means; positions scatter {:.1f} m about them)",
                       *reported_speed_mps, window_s, speed_reports, track_extent_m, block_scatter_m);
  return out;
}

std::string MotionCheck::describe_limits() const {
  if (reported_speed_mps)
    return fmt::format("limits read from the receiver: a reported speed of {:.2f} m/s with a track at least {:.0f}% "
                       "as fast and {:.2f} m/s, and at most {:.0f}x as fast (a faster track is position error, not "
                       "motion), and a smoothed track spanning more than {:.1f} m ({:.0f}x the positions' scatter "
                       "about it: a track within its own scatter is noise)", kReportedSpeedLimit_mps,
                       100 * kTrackShareOfReported, kMinTrackSpeed_mps, kTrackMultipleOfReported,
                       track_extent_limit_m, kTrackExtentInScatter);
  return fmt::format("limits for this log's noise ({:.2f} m about a straight line, {:.3f} m first differences): "
                     "{:.1f} m and {:.2f} m/s", noise_sd_m, noise_d1_sd_m, displacement_limit_m, speed_limit_mps);
}

namespace {

// Median over windows of `window_s` of the mean reported speed in each window.
std::optional<double> sustained_reported_speed(std::span<const SpeedReport> speeds, double window_s) {
  if (speeds.empty() || !(window_s > 0.0)) return std::nullopt;
  std::vector<double> means;
  double sum = 0.0, count = 0.0;
  auto bucket = static_cast<long long>(std::floor(speeds.front().time_s / window_s));
  for (const SpeedReport& r : speeds) {
    const auto b = static_cast<long long>(std::floor(r.time_s / window_s));
    if (b != bucket && count > 0.0) means.push_back(sum / count), sum = count = 0.0;
    bucket = b;
    sum += r.speed_mps, count += 1.0;
  }
  if (count > 0.0) means.push_back(sum / count);
  std::nth_element(means.begin(), means.begin() + static_cast<std::ptrdiff_t>(means.size() / 2), means.end());
  return means[means.size() / 2];
}

// The smoothed track of the series: the mean horizontal positions of `blocks` consecutive blocks
// of samples (those with a fix), the largest distance between two of them, and the rms distance of
// the positions from their own block's mean.
void smoothed_track(const EnuSeries& s, int blocks, double& extent_m, double& scatter_m) {
  const std::size_t n = s.size();
  std::vector<std::array<double, 2>> means;
  double sum2 = 0.0, count = 0.0;
  for (int b = 0; b < blocks; ++b) {
    const std::size_t from = n * static_cast<std::size_t>(b) / static_cast<std::size_t>(blocks);
    const std::size_t to = n * static_cast<std::size_t>(b + 1) / static_cast<std::size_t>(blocks);
    double e = 0.0, no = 0.0;
    if (!mean_over(s, from, to, e, no)) continue;
    means.push_back({e, no});
    for (std::size_t k = from; k < to; ++k)
      if (present(s, k)) {
        sum2 += std::pow(s.axis_m[0][k] - e, 2) + std::pow(s.axis_m[1][k] - no, 2);
        count += 1.0;
      }
  }
  extent_m = 0.0;
  for (std::size_t i = 0; i < means.size(); ++i)
    for (std::size_t j = i + 1; j < means.size(); ++j)
      extent_m = std::max(extent_m, std::hypot(means[i][0] - means[j][0], means[i][1] - means[j][1]));
  scatter_m = count > 0.0 ? std::sqrt(sum2 / count) : 0.0;
}

}  // namespace

MotionCheck check_motion(const EnuSeries& s, std::span<const SpeedReport> reports) {
  MotionCheck m;
  const std::size_t n = s.size();
  const std::size_t tenth = std::max<std::size_t>(1, n / 10);
  double e0 = 0, n0 = 0, e1 = 0, n1 = 0;
  if (mean_over(s, 0, tenth, e0, n0) && mean_over(s, n - tenth, n, e1, n1)) m.displacement_m = std::hypot(e1 - e0, n1 - n0);
  m.window_s = std::min(kSpeedWindow_s, s.duration_s() / 3.0);
  const auto lag = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(m.window_s * s.rate_hz)));
  m.window_s = static_cast<double>(lag) / s.rate_hz;
  std::vector<double> speeds;
  for (std::size_t k = lag; k < n; ++k)
    if (present(s, k) && present(s, k - lag))
      speeds.push_back(std::hypot(s.axis_m[0][k] - s.axis_m[0][k - lag], s.axis_m[1][k] - s.axis_m[1][k - lag]) /
                       m.window_s);
  if (!speeds.empty()) {
    std::nth_element(speeds.begin(), speeds.begin() + static_cast<std::ptrdiff_t>(speeds.size() / 2), speeds.end());
    m.speed_mps = speeds[speeds.size() / 2];
  }
  EnuSeries smooth_removed = s;
  (void)detrend(smooth_removed);
  m.noise_sd_m = std::hypot(sd_about_line(s.axis_m[0]), sd_about_line(s.axis_m[1]));
  m.noise_d1_sd_m = std::hypot(first_difference_sd(smooth_removed.axis_m[0]), first_difference_sd(smooth_removed.axis_m[1]));
  m.displacement_limit_m = std::max(kMinDisplacementLimit_m, kDisplacementInSd * m.noise_sd_m);
  m.speed_limit_mps = std::max(kMinSpeedLimit_mps, kSpeedInWalks * m.noise_d1_sd_m *
                                                       std::sqrt(static_cast<double>(lag)) / m.window_s);
  m.speed_reports = reports.size();
  m.reported_speed_mps = sustained_reported_speed(reports, m.window_s);
  smoothed_track(s, kTrackBlocks, m.track_extent_m, m.block_scatter_m);
  m.track_extent_limit_m = std::max(kMinDisplacementLimit_m, kTrackExtentInScatter * m.block_scatter_m);
  if (m.reported_speed_mps) {
    m.moving = *m.reported_speed_mps >= kReportedSpeedLimit_mps &&
               m.speed_mps >= std::max(kMinTrackSpeed_mps, kTrackShareOfReported * *m.reported_speed_mps) &&
               m.speed_mps <= kTrackMultipleOfReported * *m.reported_speed_mps &&
               m.track_extent_m > m.track_extent_limit_m;
  } else {
    m.moving = m.displacement_m > m.displacement_limit_m || m.speed_mps > m.speed_limit_mps;
  }
  return m;
}

Detrended detrend(EnuSeries& s) {
  const std::size_t n = s.size();
  const std::size_t half = std::max<std::size_t>(2, static_cast<std::size_t>(std::llround(0.5 * kDetrendWindow_s * s.rate_hz)));
  const std::size_t width = std::min(n, 2 * half + 1);
  std::array<std::vector<double>, 3> trend;
  for (std::size_t a = 0; a < 3; ++a) {
    trend[a].assign(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t lo = std::min(k >= half ? k - half : 0, n - width);
      trend[a][k] = local_quadratic(s.axis_m[a], lo, lo + width, k);
    }
  }
  Detrended d;
  double sum2 = 0.0, count = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0) d.path_m += std::hypot(trend[0][k] - trend[0][k - 1], trend[1][k] - trend[1][k - 1]);
    if (!present(s, k)) continue;
    sum2 += trend[0][k] * trend[0][k] + trend[1][k] * trend[1][k], count += 1.0;
    for (std::size_t a = 0; a < 3; ++a)
      if (!std::isnan(s.axis_m[a][k])) s.axis_m[a][k] -= trend[a][k];
  }
  d.rms_m = count > 0.0 ? std::sqrt(sum2 / count) : 0.0;
  return d;
}

}  // namespace gpsemu::calibration
