// The cgrw noise model: three independent concentration gradient random walks (east, north, up)
// fitted to the user's statistics, stepped at the rate those were measured at and evaluated at
// any time by cubic Hermite interpolation, so the output's statistics per unit of time do not
// depend on the output rate.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "emulator/model/noise/cgrw_fit.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/noise/rng.hpp"

namespace gpsemu::noise {

/// The preset's shape (ratios to the width, at 1 Hz over 5-minute windows), between the u-blox
/// ZED-F9P's east and north axes in data/real (0.13/0.067, 0.14/0.076, 0.017/0.011): smooth
/// wander, lag-1 autocorrelation about 0.997, position standard deviation about 0.25x the width
/// and 12x the first difference's (real receivers: 0.26-0.33x, 6-29x, 0.97-0.999). Its
/// width_d2/sigma_d2 of 6.4 is within what Gaussian innovations can give (see cgrw_fit.hpp).
inline constexpr double kPresetD1PerWidth = 0.06;
inline constexpr double kPresetD2PerWidth = 0.07;
inline constexpr double kPresetSigmaD2PerWidth = 0.011;
inline constexpr double kPresetUpPerHorizontal = 1.5;

/// Checks rate_hz, window_s and the three axes; throws std::invalid_argument naming
/// `cgrw.<field>` or `cgrw.<axis>.<field>`.
void validate_cgrw_params(const CgrwParams& params);

class CgrwNoise final : public NoiseModel {
 public:
  /// Fits the three axes (may take a few milliseconds per new shape) and runs the burn-in.
  /// Axis i (east 0, north 1, up 2) draws from Rng(seed, i).
  CgrwNoise(const CgrwParams& params, std::uint64_t seed);

  /// The walk at `since_start`: between steps k and k+1 of the walk (k = floor(t * rate_hz)) a
  /// cubic Hermite curve through p_k and p_{k+1} whose slopes are the walk's per-step velocities
  /// averaged over the steps into and out of each node. On the step grid it returns the walk's
  /// samples exactly. Steps are generated lazily; a query before the buffered steps replays the
  /// walk from the start (same result, slower). Negative times count as 0. No allocation.
  [[nodiscard]] Enu offset_at(std::chrono::nanoseconds since_start) override;

  /// The fitted walk of each axis (east, north, up).
  [[nodiscard]] const std::array<CgrwFit, 3>& fits() const { return fits_; }

 private:
  struct Axis {
    CgrwInternal k;
    Rng rng;
    double p_m = 0.0, v_m = 0.0;  // the walk's state after its latest step
    std::array<double, 4> node_m{};  // p at steps base-1, base, base+1, base+2
    void step() { cgrw_step(k, rng.normal(), p_m, v_m); }
  };
  void restart();
  void advance_to(std::int64_t base);

  std::array<CgrwFit, 3> fits_;
  std::array<Axis, 3> axes_;
  double rate_hz_;
  std::size_t burn_in_steps_;
  std::int64_t base_ = 0;  // step index of node_m[1]
};

}  // namespace gpsemu::noise
