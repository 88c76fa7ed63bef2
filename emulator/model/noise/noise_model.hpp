// Position noise models: a seeded, deterministic error in local East/North/Up metres as a
// function of time since the first epoch. Pure: no clocks, no I/O.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "emulator/model/enu.hpp"

namespace gpsemu::noise {

/// The report's four cgrw parameters for one axis, all measured on a stationary receiver's log
/// at the rate `CgrwParams::rate_hz` (see docs/design.md "Noise models").
struct CgrwAxis {
  double width_m = 1.0;     ///< max - min of the position (metres)
  double width_d1_m = 0.15; ///< max - min of the first difference (metres per sample)
  double width_d2_m = 0.2;  ///< max - min of the second difference (metres per sample^2)
  double sigma_d2_m = 0.03; ///< standard deviation of the second difference (metres per sample^2)
};

struct CgrwParams {
  CgrwAxis east, north, up;
  double rate_hz = 1.0;  ///< rate the parameters were measured at (Hz); the walk steps at this rate
  /// Length of the windows the widths were measured over (seconds): max - min grows with the
  /// window, so the walk is fitted to the mean statistics over windows of this length.
  double window_s = 300.0;
};

/// Independent white noise per axis (Chrono's ChNoiseNormal; the report's Fig. 9 baseline).
struct GaussianAxis {
  double mean_m = 0.0;
  double sigma_m = 1.0;
};

/// Project Chrono 9's ChNoiseRandomWalks(mean, sigma, noise_model_update_rate, max_velocity,
/// max_acceleration), the same numbers a PyChrono user passes (see chrono_model.hpp). One set for
/// the three axes (Chrono clamps the 3-D velocity length).
struct ChronoParams {
  double mean = 0.0;            ///< accepted and ignored, as in Chrono 9's arithmetic (metres/s^2)
  double sigma = 0.0163;        ///< acceleration draw standard deviation (metres/s^2)
  double update_rate_hz = 1.0;  ///< steps per second of the walk (Hz)
  double v_max_mps = 0.03;      ///< bound on the 3-D velocity length (metres/s)
  double a_max_mps2 = 0.005;    ///< per-axis clamp of the acceleration draw (metres/s^2)
};

/// First-order Gauss-Markov process of one axis: stationary standard deviation and correlation
/// time (autocorrelation exp(-|dt|/tau)).
struct GaussMarkovAxis {
  double sigma_m = 1.0;  ///< stationary standard deviation (metres)
  double tau_s = 60.0;   ///< correlation time (seconds)
};

/// The composite model's white jitter and jump process on one axis (composite_model.hpp).
struct CompositeAxis {
  double jitter_sigma_m = 0.0;  ///< white noise standard deviation, one draw per epoch (metres)
  double jump_rate_hz = 0.0;    ///< jumps per second (a Poisson process; 0 = none)
  double jump_sigma_m = 0.0;    ///< jump size: normal, this standard deviation (metres)
  double jump_decay_s = 0.0;    ///< time constant a jump decays back with (seconds); 0 = jumps stay
  /// A slow wander besides the smooth one: second-order Gauss-Markov (smooth: it adds correlation,
  /// not first differences), stationary standard deviation (metres; 0 = none) and correlation time
  /// (seconds, > 0 when the deviation is): the correlation a receiver keeps over tens of seconds to
  /// minutes, bounded however long the run.
  double slow_sigma_m = 0.0;
  double slow_tau_s = 0.0;
};

/// The composite model's smooth component.
enum class CompositeSmooth { gauss_markov_2, cgrw };

/// `composite`: a smooth component + a slow component + white jitter + a jump process, per axis.
struct CompositeParams {
  CompositeSmooth smooth = CompositeSmooth::gauss_markov_2;
  /// The smooth component when gauss_markov_2 (second-order Gauss-Markov).
  std::array<GaussMarkovAxis, 3> smooth_gm{{{0.5, 20.0}, {0.5, 20.0}, {1.0, 20.0}}};
  /// The smooth component's walk axes when cgrw (`composite-cgrw-*`; its rate and window are
  /// NoiseConfig::cgrw's); empty: NoiseConfig::cgrw itself. A calibrated composite's walk has its
  /// own scale (it shares the variance with the slow part and jitter), so it has its own keys.
  std::optional<std::array<CgrwAxis, 3>> smooth_cgrw;
  std::array<CompositeAxis, 3> axes{};  ///< east, north, up
};

enum class Model { none, cgrw, chrono, gaussian, gauss_markov, composite };

struct NoiseConfig {
  Model model = Model::cgrw;
  CgrwParams cgrw;                          ///< used when model == cgrw
  ChronoParams chrono;                      ///< used when model == chrono
  std::array<GaussianAxis, 3> gaussian{};   ///< east, north, up; used when model == gaussian
  std::array<GaussMarkovAxis, 3> gauss_markov{};  ///< east, north, up; model == gauss_markov
  int gauss_markov_order = 1;  ///< 1: first order; 2: second order, critically damped (smooth)
  CompositeParams composite;   ///< used when model == composite
};

/// The report's "one knob": cgrw parameters for a receiver whose horizontal position wanders over
/// `width_m` (max - min); 0.1 m high accuracy, 1 m preset, 10 m low accuracy. Up gets 1.5x.
[[nodiscard]] CgrwParams cgrw_preset(double width_m);

/// A noise process. Query with non-decreasing `since_start`; the same seed and query times give
/// the same values on every platform.
class NoiseModel {
 public:
  virtual ~NoiseModel() = default;
  /// The error at `since_start` after the first epoch (metres, local ENU).
  [[nodiscard]] virtual Enu offset_at(std::chrono::nanoseconds since_start) = 0;
};

/// Builds the configured model. Throws std::invalid_argument naming the bad parameter.
[[nodiscard]] std::unique_ptr<NoiseModel> make_noise_model(const NoiseConfig& config,
                                                           std::uint64_t seed);

/// Parses "none", "cgrw", "chrono", "gaussian", "gauss-markov", "composite"; throws std::invalid_argument listing the accepted names.
[[nodiscard]] Model parse_model(const std::string& name);
[[nodiscard]] std::string to_string(Model model);

}  // namespace gpsemu::noise
