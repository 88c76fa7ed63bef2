// The velocity error (emulator/model/noise/velocity_noise.hpp) fitted from a stationary receiver's
// reported speeds over ground (RMC, else VTG). At rest the speed is the horizontal velocity error's
// length: with the same Gaussian error on both axes (white plus Gauss-Markov, sigma per axis s) it
// is Rayleigh, so mean(speed^2) = 2 s^2. A chipset that clamps a slow speed to 0 (Quectel,
// SkyTraq, SiRF) reports only the tail above its clamp c: P(speed > c) = exp(-c^2 / 2 s^2) (the
// share reported) and E[speed^2 | speed > c] = c^2 + 2 s^2 give both s and c. The white and wandering
// parts split by the lag-1 correlation of speed^2 (|rho|^2 of the per-axis correlation rho, which
// is the wander's share times exp(-dt / tau)), at the model's correlation time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "emulator/calibration/receiver_log.hpp"
#include "emulator/model/noise/velocity_noise.hpp"

namespace gpsemu::calibration {

/// A log with more than this share of zero speeds is a clamping chipset's.
inline constexpr double kClampZeroShare = 0.3;
/// Fewer speed reports than this fit nothing.
inline constexpr std::size_t kMinSpeedReports = 30;
/// A clamping chipset's speeds above 0 needed to fit its clamp and sigma from them.
inline constexpr std::size_t kMinSpeedsAboveClamp = 5;
/// A clamping chipset that never reports a speed above 0 at rest: the clamp written (m/s), the
/// sigma then left at the model's default (nothing in the log tells it).
inline constexpr double kAllZeroClamp_mps = 0.3;

struct VelocityFit {
  std::size_t reports = 0;       ///< speeds read
  double median_mps = 0.0;       ///< of the reported speeds
  double p95_mps = 0.0;
  double zero_share = 0.0;       ///< reported exactly 0
  double lag1_corr = 0.0;        ///< of speed^2 between consecutive reports (clamped logs: 0)
  bool fitted = false;           ///< enough reports; params is the fit
  noise::VelocityNoiseParams params;  ///< the fitted model (defaults when not fitted)
  /// The fitted model's speeds at rest, simulated at the log's interval (clamp applied): what the
  /// emulator reports with the calibrated file.
  double model_median_mps = 0.0;
  double model_p95_mps = 0.0;
};

/// Median and p95 of the speed at rest `params` gives over `epochs` epochs `interval_s` apart.
struct SpeedQuantiles {
  double median_mps = 0.0, p95_mps = 0.0;
};
[[nodiscard]] SpeedQuantiles simulated_speeds(const noise::VelocityNoiseParams& params, double interval_s,
                                              std::size_t epochs, std::uint64_t seed);

/// Fits the velocity error from the speeds of a stationary log whose epochs are `interval_s` apart.
/// The model's speeds are simulated from `seed`.
[[nodiscard]] VelocityFit fit_velocity(std::span<const SpeedReport> speeds, double interval_s, std::uint64_t seed);

/// The config keys velocity-noise, velocity-wander, velocity-wander-tau, velocity-static-clamp,
/// with a comment (nothing but the comment when not fitted).
[[nodiscard]] std::string velocity_toml(const VelocityFit& fit);

/// One line for a person: the reported speeds and the fit.
[[nodiscard]] std::string velocity_summary(const VelocityFit& fit);

}  // namespace gpsemu::calibration
