// The velocity a receiver reports is measured apart from its position: from the carriers' Doppler
// shifts, not by differencing positions. So its error is not the derivative of the position's
// wander. Per axis (east, north, up) it is white noise (the Doppler tracking loops' jitter) plus a
// slow correlated part (a first-order Gauss-Markov process: multipath, the clock's frequency
// wander), independent of the position noise (docs/noise-and-calibration.md, "Velocity").
// Real receivers at rest report 0.02-0.10 m/s (u-blox M8/F9, SiRF); some chipsets clamp a slow
// speed to exactly 0 when they think they stand still (Quectel, SkyTraq): static_clamp_mps.
// Pure and deterministic given the seed (its own stream of the run's seed).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "emulator/model/enu.hpp"
#include "emulator/model/noise/rng.hpp"

namespace gpsemu::noise {

struct VelocityNoiseParams {
  double white_sigma_mps = 0.03;   ///< white part, 1 sigma per horizontal axis (m/s)
  double wander_sigma_mps = 0.02;  ///< correlated part's stationary sigma per horizontal axis (m/s)
  double wander_tau_s = 10.0;      ///< its correlation time (seconds), > 0
  double vertical_ratio = 1.6;     ///< the up axis's sigmas over the horizontal ones (VDOP / HDOP, typically)
  /// Below this horizontal speed (m/s) the receiver reports 0 (and no course); 0: never.
  double static_clamp_mps = 0.0;

  /// Both parts zero: the truth's velocity (--velocity-noise 0).
  [[nodiscard]] bool off() const { return white_sigma_mps == 0.0 && wander_sigma_mps == 0.0; }
  /// The per-axis 1-sigma of the whole error, horizontal (m/s): sqrt(white^2 + wander^2).
  [[nodiscard]] double horizontal_sigma_mps() const;
};

/// Throws std::invalid_argument naming the parameter out of range (sigmas 0..10 m/s, tau
/// 0.1..86400 s, ratio 0.1..10, clamp 0..1 m/s).
void validate(const VelocityNoiseParams& params);

class VelocityNoise {
 public:
  /// Throws std::invalid_argument (validate) for parameters out of range.
  VelocityNoise(const VelocityNoiseParams& params, std::uint64_t seed);
  /// The error at `since_start` (non-decreasing; the correlated part steps by the time since
  /// the last call, exactly discretised, so any epoch rate gives the same statistics).
  [[nodiscard]] Enu error_at(std::chrono::nanoseconds since_start);
  /// Back to the first value (a cold start).
  void reset();
  [[nodiscard]] const VelocityNoiseParams& params() const { return params_; }

 private:
  VelocityNoiseParams params_;
  Rng rng_;
  Enu wander_{};
  std::optional<std::chrono::nanoseconds> last_;
  // The step's coefficients for the last interval (an epoch grid repeats it: exp and sqrt once).
  std::chrono::nanoseconds step_dt_{-1};
  double step_a_ = 0.0, step_b_ = 0.0;
};

}  // namespace gpsemu::noise
