// Calibration of every noise model from a stationary receiver's log, and their comparison with
// it (docs/design.md "Calibration"): the log's statistics per axis, the cgrw statistics and fit, the
// gaussian and gauss-markov parameters, a chrono fit, then each model simulated over the log's
// duration, rate and gaps with the log's output resolution applied (through the emulator's own
// GGA formatter and parser), scored against the log, and written as a config file the emulator
// loads as it is.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "emulator/calibration/hold_fit.hpp"
#include "emulator/calibration/model_fits.hpp"
#include "emulator/calibration/motion.hpp"
#include "emulator/calibration/receiver_log.hpp"
#include "emulator/calibration/velocity_fit.hpp"
#include "emulator/calibration/series_stats.hpp"
#include "emulator/model/noise/cgrw_fit.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/static_hold.hpp"

namespace gpsemu::calibration {

struct CalibrateOptions {
  std::uint64_t seed = 1;  ///< runs use seeds seed, seed + 1, ...
  int runs = 32;           ///< simulated runs per model (statistics are averaged over them; 8 runs of a
                           ///< log of a few minutes vary by 20% between seed sets)
  /// Remove a smooth trajectory first (motion.hpp) instead of refusing a log that moves.
  bool detrend = false;
  /// At most this many grid epochs (to_enu_series); `max_epochs_reason` says why, in its message.
  std::size_t max_epochs = kMaxCalibrationEpochs;
  std::string max_epochs_reason = "";
};

/// Peak memory of calibrate, compare and judge per grid epoch of the log (bytes; measured with
/// /usr/bin/time -v on 880 000 epochs, docs/performance.md), the file itself not held.
inline constexpr std::size_t kCalibrationBytesPerEpoch = 600;

/// The epochs `available_bytes` of memory calibrate (at kCalibrationBytesPerEpoch, half the memory
/// left for the rest of the machine), at most kMaxCalibrationEpochs.
[[nodiscard]] std::size_t max_epochs_for_memory(std::uint64_t available_bytes);

/// One model with its calibrated parameters and how it compares.
struct ModelResult {
  noise::NoiseConfig config;              ///< model and parameters, ready for make_noise_model
  /// The median over the runs (each run a window of the log's length: what a typical run looks
  /// like), east north up; the score is of these.
  std::array<AxisStats, 3> stats;
  std::array<AxisStats, 3> low, high;     ///< the 10th and 90th percentiles over the runs
  double score = 0.0;                     ///< calibration::score against the log (0 = perfect)
  std::array<std::vector<double>, 3> first_run_m;  ///< the first run's series (for plots)
};

struct Calibration {
  EnuSeries series;                       ///< the log on its grid, metres about its mean
  LogCounts counts;                       ///< what reading it skipped
  MotionCheck motion;                     ///< the log's displacement and speed (before any detrending)
  VelocityFit velocity;                   ///< the velocity error, from the speeds reported at rest
  std::array<AxisStats, 3> real;          ///< the log's statistics
  std::size_t window_samples = 0;         ///< cgrw window (the log's length, at most 100 000)
  /// cgrw: the measured four statistics, the best compromise fit of each (max_ratio infinite),
  /// and what is written (measured, or the fit's achieved statistics when the walk cannot get
  /// within the emulator's accepted factor of 2). Empty reason = usable.
  std::array<noise::CgrwAxis, 3> cgrw_measured{};
  std::array<noise::CgrwFit, 3> cgrw_fit{};
  std::string cgrw_unusable;
  /// What calibration changed to make every model load: constant axes set to no noise,
  /// statistics nudged into a model's valid region, de-quantisation (written as comments).
  std::vector<std::string> notes;
  std::vector<ModelResult> models;        ///< cgrw (if usable), chrono, gaussian, gauss-markov 1, 2, composite
  /// The composite's smooth part: both are fitted (gauss-markov-2 and cgrw, each with jitter and
  /// jumps) and scored like every model; models holds the better, these say which and both scores
  /// (cgrw_score infinite when the walk could not be fitted).
  struct CompositeChoice {
    std::string smooth = "gauss-markov-2";
    double gm2_score = 0.0, cgrw_score = 0.0;
    [[nodiscard]] std::string describe() const;
  } composite;
  std::size_t best = 0;                   ///< index of the lowest score in models
  HoldFit hold;                           ///< static hold and altitude decimals (hold_fit.hpp)
};

/// Reads nothing: works on a log already read. Throws std::invalid_argument when the log is
/// unusable (too few fixes, no spread at all), MotionError when it moves (unless
/// options.detrend).
[[nodiscard]] Calibration calibrate(ReceiverLog log, const CalibrateOptions& options = {});

/// `config` simulated at the series' epochs (rate, length, gaps as NaN), with the emulator's
/// output resolution applied: each position is formatted as the emulator's GGA at
/// `series.minute_decimals` (altitude at `series.alt_decimals`, at most 4) and parsed back, about
/// `series.centre`; with `hold` enabled, through the receiver's static hold (standing still).
[[nodiscard]] std::array<std::vector<double>, 3> simulate(const noise::NoiseConfig& config,
                                                          const EnuSeries& series,
                                                          std::uint64_t seed,
                                                          const StaticHoldOptions& hold = {});

/// Calls `run(r)` for r = 0 .. runs - 1, the runs spread over the machine's cores, in any order:
/// each call writes its result in its run's place, so what follows is the same whatever the number
/// of threads. Rethrows the first exception a run threw, once every run is done.
void for_each_run(std::size_t runs, const std::function<void(std::size_t)>& run);

/// The calibrated config file (TOML): noise (the best model), rate, resolution, origin, and the
/// keys of every model, with a header of comments saying where it comes from.
[[nodiscard]] std::string config_toml(const Calibration& c, const std::string& log_name);

/// The statistics of `config` simulated `runs` times (seeds seed, seed + 1, ...) at the series'
/// epochs and resolution (simulate, through `hold` when enabled), averaged; `first_run` (if given)
/// gets the first run's series, `per_run` (if given) each run's statistics.
[[nodiscard]] std::array<AxisStats, 3> simulated_stats(const noise::NoiseConfig& config, const EnuSeries& series,
                                                       std::size_t window, std::uint64_t seed, int runs,
                                                       std::array<std::vector<double>, 3>* first_run,
                                                       std::array<std::vector<AxisStats>, 3>* per_run = nullptr,
                                                       const StaticHoldOptions& hold = {});

/// The name a model is shown under: its noise name, "gauss-markov-2" for the second order.
[[nodiscard]] std::string model_label(const noise::NoiseConfig& config);

}  // namespace gpsemu::calibration
