// The concentration gradient random walk (cgrw, SBEL TR-2022-02 "Using random walks to simulate
// GPS sensing") for one axis: its internal parameters and step, the report's four statistics of a
// sample series, and the deterministic fit from those statistics to internal parameters. Used by
// the cgrw noise model and reusable by calibration.
//
// One step, per sample at the rate the statistics were measured at (units: metres and samples):
//   m = -sigma * p / p_max;   a ~ N(m, sigma) clamped to +-a_max;   v = clamp(v + a, +-v_max);
//   p = p + v
// Deliberate deviation from docs/design.md's literal m = -p / p_max: with metres as units that pull is
// 1 m/sample^2 at p = p_max, which for sub-metre receivers collapses the walk into near-white
// noise (measured lag-1 autocorrelation 0.25-0.8 at 1 Hz, where real receivers show 0.97-0.999).
// Expressing the gradient in units of sigma keeps a smooth wander, and makes the model
// scale-invariant: multiplying the four internal parameters by k multiplies the path by k. The
// achievable family is the same (p_max is free either way); only the parametrisation differs.
//
// Known limit: the innovations are Gaussian, so the walk's width_d2_m / sigma_d2_m stays below
// about 6.5 over 300-sample windows. Receivers with jumps (Telit, Quectel: 14-17) cannot be
// matched on all four statistics; the fit then returns a least-squares compromise and says how
// far it is (CgrwFit::worst_ratio).
#pragma once

#include <algorithm>
#include <cstddef>
#include <span>
#include <string_view>

#include "emulator/model/noise/noise_model.hpp"

namespace gpsemu::noise {

/// The walk's own parameters (not the user's statistics), per sample of the walk's rate.
struct CgrwInternal {
  double p_max_m = 1.0;  ///< deviation at which the mean pull equals sigma (metres)
  double v_max_m = 0.1;  ///< clamp of the velocity (metres per sample)
  double a_max_m = 0.1;  ///< clamp of the acceleration draw (metres per sample^2)
  double sigma_m = 0.01; ///< standard deviation of the acceleration draw (metres per sample^2)
};

/// One step of the walk, given one standard normal draw. No allocation, no branches on state
/// other than the clamps.
inline void cgrw_step(const CgrwInternal& k, double standard_normal, double& p_m,
                      double& v_m) noexcept {
  const double a_m = std::clamp(k.sigma_m * (standard_normal - p_m / k.p_max_m), -k.a_max_m,
                                k.a_max_m);
  v_m = std::clamp(v_m + a_m, -k.v_max_m, k.v_max_m);
  p_m += v_m;
}

/// The report's four statistics of one series: max - min of the samples, of their first
/// difference and of their second difference, and the (population) standard deviation of the
/// second difference, in metres per sample^n. Throws std::invalid_argument below 3 samples.
[[nodiscard]] CgrwAxis measure_cgrw_axis(std::span<const double> samples);

/// The mean of measure_cgrw_axis over consecutive, non-overlapping windows of `window_samples`
/// (a trailing partial window is ignored). Throws if there is not one whole window or
/// window_samples < 3.
[[nodiscard]] CgrwAxis mean_cgrw_statistics(std::span<const double> samples,
                                            std::size_t window_samples);

/// True when the four statistics are all 0: the axis has no noise (a constant axis of a log).
[[nodiscard]] inline bool cgrw_axis_off(const CgrwAxis& s) {
  return s.width_m == 0.0 && s.width_d1_m == 0.0 && s.width_d2_m == 0.0 && s.sigma_d2_m == 0.0;
}

/// Throws std::invalid_argument naming `<name>.<field>` unless the four statistics are all 0 (the
/// axis is off) or positive, finite and possible for some series (width_d1 <= 2 width,
/// width_d2 <= 2 width_d1, width_d2 >= 2 sigma_d2).
void validate_cgrw_axis(const CgrwAxis& stats, std::string_view name);

/// Result of fit_cgrw_axis.
struct CgrwFit {
  CgrwInternal internal;   ///< the walk's parameters
  CgrwAxis achieved;       ///< mean statistics of the fitted walk over the fit's windows
  double worst_ratio = 1;  ///< max over the four of max(achieved/target, target/achieved)
  int iterations = 0;      ///< Levenberg-Marquardt iterations used (0 when cached)
};

/// Largest worst_ratio fit_cgrw_axis accepts before it throws.
inline constexpr double kCgrwMaxFitRatio = 2.0;
/// Allowed window lengths (in samples of the walk's rate) for the fit.
inline constexpr double kCgrwMinWindowSamples = 16.0;
inline constexpr double kCgrwMaxWindowSamples = 100000.0;

/// The nearest statistics to `s` that validate_cgrw_axis accepts with a margin of 1% on each
/// inequality (so they still hold after printing with 6 significant digits): width_d1 and
/// width_d2 lowered to their bounds, sigma_d2 lowered to width_d2 / 2. Non-positive or
/// non-finite widths, or width 0, give the axis off (all 0). `changed` says whether anything moved.
[[nodiscard]] CgrwAxis nudge_cgrw_axis(const CgrwAxis& s, bool* changed = nullptr);

/// Internal parameters whose walk has, on average over windows of `window_samples`, the four
/// statistics `target`. Deterministic: simulates with a fixed internal seed (common random
/// numbers) over 32 windows (fewer, down to 8, beyond 10 000 samples a window) after a burn-in,
/// and minimises the weighted squared log-ratios of measured to target statistics (width
/// weighted 4x) by Levenberg-Marquardt over the logs of the four internal parameters with a
/// finite-difference Jacobian. Fits are done at unit width and
/// scaled (the model is scale-invariant), and cached per shape and window length. An axis that
/// is off (cgrw_axis_off) gives a walk that stays at 0 (sigma, v_max, a_max 0). Throws
/// std::invalid_argument naming `<name>.<field>` for invalid statistics or window, or when the
/// best fit is still off by more than `max_ratio` (calibration may pass infinity to get the
/// best compromise and report it).
[[nodiscard]] CgrwFit fit_cgrw_axis(const CgrwAxis& target, double window_samples,
                                    std::string_view name = "cgrw",
                                    double max_ratio = kCgrwMaxFitRatio);

/// Steps to run before the first output so the walk starts in its stationary regime: at least a
/// window, enough for the velocity to reach its clamp and for four periods of the pull.
[[nodiscard]] std::size_t cgrw_burn_in_steps(const CgrwInternal& internal, double window_samples);

}  // namespace gpsemu::noise
