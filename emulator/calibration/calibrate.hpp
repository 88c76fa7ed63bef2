// Calibration of every noise model from a stationary receiver's log, and their comparison with
// it (docs/design.md "Calibration"): the log's statistics per axis, the cgrw statistics and fit, the
// gaussian and gauss-markov parameters, a chrono fit, then each model simulated over the log's
// duration, rate and gaps with the log's output resolution applied (through the emulator's own
// GGA formatter and parser), scored against the log, and written as a config file the emulator
// loads as it is.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "emulator/calibration/receiver_log.hpp"
#include "emulator/calibration/series_stats.hpp"
#include "emulator/model/noise/cgrw_fit.hpp"
#include "emulator/model/noise/noise_model.hpp"

namespace gpsemu::calibration {

struct CalibrateOptions {
  std::uint64_t seed = 1;  ///< runs use seeds seed, seed + 1, ...
  int runs = 8;            ///< simulated runs per model (statistics are averaged over them)
};

/// One model with its calibrated parameters and how it compares.
struct ModelResult {
  noise::NoiseConfig config;              ///< model and parameters, ready for make_noise_model
  std::array<AxisStats, 3> stats;         ///< mean over the runs, east north up
  double score = 0.0;                     ///< calibration::score against the log (0 = perfect)
  std::array<std::vector<double>, 3> first_run_m;  ///< the first run's series (for plots)
};

struct Calibration {
  EnuSeries series;                       ///< the log on its grid, metres about its mean
  LogCounts counts;                       ///< what reading it skipped
  std::array<AxisStats, 3> real;          ///< the log's statistics
  std::size_t window_samples = 0;         ///< cgrw window (the log's length, at most 100 000)
  /// cgrw: the measured four statistics, the best compromise fit of each (max_ratio infinite),
  /// and what is written (measured, or the fit's achieved statistics when the walk cannot get
  /// within the emulator's accepted factor of 2). Empty reason = usable.
  std::array<noise::CgrwAxis, 3> cgrw_measured{};
  std::array<noise::CgrwFit, 3> cgrw_fit{};
  std::string cgrw_unusable;
  std::vector<ModelResult> models;        ///< cgrw (if usable), chrono, gaussian, gauss-markov 1, 2
  std::size_t best = 0;                   ///< index of the lowest score in models
};

/// Reads nothing: works on a log already read. Throws std::invalid_argument when the log is
/// unusable (too few fixes, no spread at all).
[[nodiscard]] Calibration calibrate(ReceiverLog log, const CalibrateOptions& options = {});

/// `config` simulated at the series' epochs (rate, length, gaps as NaN), with the emulator's
/// output resolution applied: each position is formatted as the emulator's GGA at
/// `series.minute_decimals` (altitude 0.1 m) and parsed back, about `series.centre`.
[[nodiscard]] std::array<std::vector<double>, 3> simulate(const noise::NoiseConfig& config,
                                                          const EnuSeries& series,
                                                          std::uint64_t seed);

/// The calibrated config file (TOML): noise (the best model), rate, resolution, origin, and the
/// keys of every model, with a header of comments saying where it comes from.
[[nodiscard]] std::string config_toml(const Calibration& c, const std::string& log_name);

/// Chrono's parameters whose walk, at the log's rate, best matches the log (Nelder-Mead on the
/// score of 2 runs over log sigma, log v_max, log a_max; deterministic).
[[nodiscard]] noise::ChronoParams fit_chrono(const EnuSeries& series,
                                             const std::array<AxisStats, 3>& real);

/// Gauss-Markov parameters of one axis for the process of `order` (1 or 2): tau such that the
/// expected lag-1 behaviour of a log of this length matches it (expected first-difference
/// variance over expected sample variance about the mean equal to the log's), sigma such that
/// the expected sample standard deviation over the log's length equals the log's (the variance
/// lost to the mean removed is put back, at most a factor 5 in sigma). When no tau reaches the
/// log's ratio (order 1 on smooth receivers), the nearest end of [0.05 samples, 10 x the log's
/// length] is taken.
[[nodiscard]] noise::GaussMarkovAxis fit_gauss_markov(std::span<const double> x, double rate_hz,
                                                      int order);
/// The same from the two statistics of a series of `n` samples.
[[nodiscard]] noise::GaussMarkovAxis fit_gauss_markov(double sd_m, double d1_sd_m, std::size_t n,
                                                      double rate_hz, int order);

/// The name a model is shown under: its noise name, "gauss-markov-2" for the second order.
[[nodiscard]] std::string model_label(const noise::NoiseConfig& config);

}  // namespace gpsemu::calibration
