#include "emulator/calibration/velocity_fit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "emulator/model/noise/sample_stats.hpp"

namespace gpsemu::calibration {
namespace {

/// Lag-1 autocorrelation of speed^2 over consecutive reports; a pair across a gap (not one
/// interval apart) is left out, as NaN between them.
double lag1_correlation_of_squares(std::span<const SpeedReport> speeds, double interval_s) {
  std::vector<double> x;
  x.reserve(speeds.size() + speeds.size() / 8);
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    if (i > 0 && std::abs(speeds[i].time_s - speeds[i - 1].time_s - interval_s) > 0.25 * interval_s) {
      x.push_back(std::numeric_limits<double>::quiet_NaN());
    }
    const double v = speeds[i].speed_mps;
    x.push_back(v * v);
  }
  const double r = noise::autocorrelation(x, 1);
  return std::isnan(r) ? 0.0 : r;
}

}  // namespace

SpeedQuantiles simulated_speeds(const noise::VelocityNoiseParams& params, double interval_s, std::size_t epochs,
                                std::uint64_t seed) {
  noise::VelocityNoise noise(params, seed);
  std::vector<double> s;
  s.reserve(epochs);
  const auto step = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(interval_s));
  for (std::size_t k = 0; k < epochs; ++k) {
    const Enu e = noise.error_at(step * static_cast<std::int64_t>(k));
    const double speed = std::hypot(e.east_m, e.north_m);
    s.push_back(speed < params.static_clamp_mps ? 0.0 : speed);
  }
  return {noise::quantile(s, 0.5), noise::quantile(s, 0.95)};
}

VelocityFit fit_velocity(std::span<const SpeedReport> speeds, double interval_s, std::uint64_t seed) {
  VelocityFit fit;
  fit.reports = speeds.size();
  if (speeds.size() < kMinSpeedReports || !(interval_s > 0.0)) return fit;
  std::vector<double> s;
  s.reserve(speeds.size());
  double sum_sq = 0.0;
  std::size_t zeros = 0;
  for (const SpeedReport& r : speeds) {
    const double v = std::max(0.0, static_cast<double>(r.speed_mps));
    s.push_back(v);
    sum_sq += v * v;
    if (v == 0.0) ++zeros;
  }
  const auto n = static_cast<double>(s.size());
  fit.median_mps = noise::quantile(s, 0.5);
  fit.p95_mps = noise::quantile(s, 0.95);
  fit.zero_share = static_cast<double>(zeros) / n;
  fit.fitted = true;
  noise::VelocityNoiseParams& p = fit.params;
  const std::size_t above_count = s.size() - zeros;
  if (fit.zero_share > kClampZeroShare && above_count < kMinSpeedsAboveClamp) {
    p.static_clamp_mps = kAllZeroClamp_mps;  // the sigmas stay the model's: the clamp hid them whole
  } else {
    double sigma = 0.0;
    double wander_share = p.wander_sigma_mps * p.wander_sigma_mps / (p.horizontal_sigma_mps() * p.horizontal_sigma_mps());
    if (fit.zero_share > kClampZeroShare) {
      // The speeds above the clamp c are a Rayleigh tail: P(s > c) = p = exp(-c^2 / 2 sigma^2) and
      // E[s^2 | s > c] = c^2 + 2 sigma^2, so sigma^2 = E[s^2 | s > c] / (2 (1 - ln p)).
      const double above = static_cast<double>(above_count) / n;
      sigma = std::sqrt(sum_sq / static_cast<double>(above_count) / (2.0 * (1.0 - std::log(above))));
      p.static_clamp_mps = std::min(1.0, sigma * std::sqrt(-2.0 * std::log(above)));
    } else {
      sigma = std::sqrt(sum_sq / n / 2.0);
      fit.lag1_corr = lag1_correlation_of_squares(speeds, interval_s);
      const double rho_wander = std::exp(-interval_s / p.wander_tau_s);
      wander_share = std::clamp(std::sqrt(std::max(0.0, fit.lag1_corr)) / rho_wander, 0.0, 1.0);
    }
    sigma = std::min(sigma, 10.0);
    p.white_sigma_mps = sigma * std::sqrt(1.0 - wander_share);
    p.wander_sigma_mps = sigma * std::sqrt(wander_share);
  }
  const SpeedQuantiles q = simulated_speeds(p, interval_s, std::max<std::size_t>(s.size(), 2000), seed);
  fit.model_median_mps = q.median_mps, fit.model_p95_mps = q.p95_mps;
  return fit;
}

std::string velocity_toml(const VelocityFit& fit) {
  if (!fit.fitted) {
    return fmt::format("# velocity: {} speed reports, too few to fit (at least {}): the model's defaults\n", fit.reports,
                       kMinSpeedReports);
  }
  const noise::VelocityNoiseParams& p = fit.params;
  std::string out = fmt::format(
      "# velocity from {} speeds at rest: median {:.3f} m/s, p95 {:.3f} m/s, {:.0f}% exactly 0, lag-1 correlation of "
      "speed^2 {:.2f}\n",
      fit.reports, fit.median_mps, fit.p95_mps, 100.0 * fit.zero_share, fit.lag1_corr);
  out += fmt::format("velocity-noise = {:.4f}\nvelocity-wander = {:.4f}\nvelocity-wander-tau = {:g}\n", p.white_sigma_mps,
                     p.wander_sigma_mps, p.wander_tau_s);
  out += fmt::format("velocity-static-clamp = {:.3f}\n", p.static_clamp_mps);
  return out;
}

std::string velocity_summary(const VelocityFit& fit) {
  if (!fit.fitted) return fmt::format("velocity: {} speed reports, not fitted (at least {})\n", fit.reports, kMinSpeedReports);
  const noise::VelocityNoiseParams& p = fit.params;
  return fmt::format(
      "velocity: {} speeds at rest, median {:.3f} m/s, p95 {:.3f} m/s, {:.0f}% zero; fitted white {:.4f} + wander {:.4f} "
      "m/s an axis (tau {:g} s), static clamp {:.3f} m/s; the fit at rest: median {:.3f} m/s, p95 {:.3f} m/s\n",
      fit.reports, fit.median_mps, fit.p95_mps, 100.0 * fit.zero_share, p.white_sigma_mps, p.wander_sigma_mps,
      p.wander_tau_s, p.static_clamp_mps, fit.model_median_mps, fit.model_p95_mps);
}

}  // namespace gpsemu::calibration
