// The `chrono` noise model: the arithmetic of Project Chrono 9's ChNoiseRandomWalks, so a PyChrono
// user can bring the parameters they already tuned. Per step of dt = 1 / update_rate_hz, with one
// set of parameters for the three axes (x east, y north, z up):
//   a_i ~ N(-0.2 * sigma * p_i, sigma) clamped to +-a_max    (gain 0.2 and p_max 1 fixed in Chrono)
//   v  += a * dt;  if |v| > v_max (3-D length): v *= v_max / |v|
//   p  += v * dt
// starting at rest at zero at the first epoch, as Chrono does at the first sensor update.
//
// Evaluation between steps: Chrono integrates up to each sensor time with a shortened last step
// (a fresh draw), so its walk depends on the sensor rate. Here the walk runs on its own fixed grid
// t_k = k / update_rate_hz and the position at t is interpolated linearly between steps k and k+1:
// during a step the integration moves p at the constant velocity v_{k+1}, so this is the path the
// arithmetic itself describes, it equals Chrono's value at every time on the grid (e.g. each 1 Hz
// epoch with a 100 Hz walk), and it does not depend on how often the emulator asks.
//
// Differences from Chrono kept on purpose: Chrono 9 stores `mean` but does not use it (kept so:
// the same numbers give the same walk); Chrono draws from std::minstd_rand seeded by the clock
// with std::normal_distribution, here from the portable seeded Rng (rng.hpp); parameters are
// doubles where Chrono takes floats.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>

#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/noise/rng.hpp"

namespace gpsemu::noise {

/// Chrono's fixed pull: mean = -kChronoGain * sigma * p / kChronoPMax.
inline constexpr double kChronoGain = 0.2;
inline constexpr double kChronoPMax = 1.0;
/// Largest update rate accepted (Hz): the walk steps lazily, one draw per axis and step.
inline constexpr double kChronoMaxRateHz = 10000.0;

/// Throws std::invalid_argument naming `chrono.<field>` unless sigma >= 0, update_rate_hz in
/// (0, kChronoMaxRateHz], v_max_mps >= 0 and a_max_mps2 >= 0, all finite (mean: finite).
void validate_chrono_params(const ChronoParams& params);

/// The walk's state after a step.
struct ChronoState {
  std::array<double, 3> p_m{};    ///< position error east, north, up (metres)
  std::array<double, 3> v_mps{};  ///< velocity of the error (metres/s)
};

/// One step of Chrono's arithmetic with the three standard normal draws `z` (east, north, up).
void chrono_step(const ChronoParams& params, const std::array<double, 3>& z, ChronoState& state);

class ChronoNoise final : public NoiseModel {
 public:
  /// Draws come from one stream, Rng(seed, 0), three per step in the order east, north, up.
  ChronoNoise(const ChronoParams& params, std::uint64_t seed);

  /// The walk at `since_start` (linear between grid steps; see the file comment). A query before
  /// the buffered step replays the walk from the start. Negative times count as 0.
  [[nodiscard]] Enu offset_at(std::chrono::nanoseconds since_start) override;

 private:
  void restart();
  void step();

  ChronoParams params_;
  Rng rng_;
  ChronoState state_;             // after step base_ + 1
  std::array<double, 3> prev_m_{};  // position after step base_
  std::int64_t base_ = 0;
};

}  // namespace gpsemu::noise
