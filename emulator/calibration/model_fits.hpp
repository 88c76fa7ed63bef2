// The fits behind `gpsemu calibrate`, one per model family, from a stationary receiver's log on
// its grid (calibrate.hpp puts them together): gauss-markov (closed-form expectations over the
// log's length), chrono (a simplex search on simulated runs), cgrw fitted to the de-quantised
// statistics and nudged into the walk's valid region, and the composite model (a smooth
// gauss-markov-2 or cgrw component, white jitter and a jump process).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "emulator/calibration/receiver_log.hpp"
#include "emulator/calibration/series_stats.hpp"
#include "emulator/model/noise/cgrw_fit.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/static_hold.hpp"

namespace gpsemu::calibration {

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
/// `max_tau_s` bounds tau (default: 10 x the log's length) and `min_kept` the variance share the
/// log is taken to show (default 1/25: sigma at most 5 x the log's standard deviation).
[[nodiscard]] noise::GaussMarkovAxis fit_gauss_markov(double sd_m, double d1_sd_m, std::size_t n,
                                                      double rate_hz, int order, double max_tau_s = 0.0,
                                                      double min_kept = 1.0 / 25.0);

/// Gauss-markov parameters of `order` refitted until their simulation at the log's rate, length,
/// gaps and resolution has the log's standard deviation and first-difference standard deviation
/// (the log's rounding coarsens its differences; the emulator rounds the same way).
[[nodiscard]] std::array<noise::GaussMarkovAxis, 3> fit_gauss_markov_dequantised(
    const EnuSeries& series, const std::array<AxisStats, 3>& real, std::size_t window, int order);

/// The cgrw statistics to write for each axis: the log's, corrected until the rounded simulation
/// has the log's statistics, nudged into the region the walk accepts (noise::nudge_cgrw_axis);
/// an axis with no spread is off (all 0). `fits` gets each axis's fit, `notes` what was changed.
[[nodiscard]] noise::CgrwParams fit_cgrw_dequantised(const EnuSeries& series,
                                                     const std::array<AxisStats, 3>& real,
                                                     std::size_t window,
                                                     std::array<noise::CgrwFit, 3>& fits,
                                                     std::vector<std::string>& notes);

/// The axes' names in notes and keys.
inline constexpr const char* kAxisNames[3] = {"east", "north", "up"};

/// One axis's cgrw statistics as written to a config file (6 significant digits) that the walk
/// reaches, from `target` over `window` samples; `fit` gets the fit (shared by the cgrw and the
/// composite fits).
[[nodiscard]] noise::CgrwAxis written_cgrw(const noise::CgrwAxis& target, double window, std::size_t axis,
                                           noise::CgrwFit& fit);

/// Each step of the composite's refit simulates about 400 000 samples: kMinRefitRuns to
/// kMaxRefitRuns runs of the log's length, and at most `max_runs` (calibrate's --runs) when that
/// is kMinRefitRuns or more.
inline constexpr int kMinRefitRuns = 8;
inline constexpr int kMaxRefitRuns = 32;
/// A quick calibration (calibrate's --runs below kMinRefitRuns: a first look, the tests' 1 or 2)
/// searches less: each refit kQuickRefitIterations steps of max(--runs, 2) runs instead of
/// kRefitIterations steps of kMinRefitRuns or more, and the slow part from its best candidate (and
/// the best no slower than the log's length) instead of its three best. Its composite is rougher;
/// every other model is fitted as in a full calibration. With --runs 8 or more nothing changes.
inline constexpr int kRefitIterations = 8;
inline constexpr int kQuickRefitIterations = 3;
[[nodiscard]] constexpr bool quick_calibration(int max_runs) { return max_runs < kMinRefitRuns; }
/// The composite model (noise::CompositeParams) of the log: jumps found in the first differences
/// (beyond 5 robust standard deviations and 2 quanta of the resolution: rate, rms size, decay of
/// the smooth component's tau), then the smooth component's sigma and tau and the white jitter
/// refitted together until the rounded simulation has the log's standard deviation, first- and
/// second-difference standard deviations. Deterministic.
/// Then the slow part (composite_model.hpp): where the log keeps more correlation at 10 and 30 s
/// than that fit, a share of its variance goes to a second-order Gauss-Markov whose share and time
/// constant are chosen to match the autocorrelation at 10 and 30 s (the fast part's own
/// autocorrelation taken from its simulation), the rest refitted as before; kept when it scores
/// better. Bounded so a run longer than the log stays within a few times its spread: every time
/// constant at most 4 times the log's length, every standard deviation at most 5 times the log's
/// (a drift-dominated log shows only a small share of a slow process's variance: tighter bounds
/// miss the Telit HE910's east sd by 31%). `notes` (if given)
/// gets what was fitted and every parameter that hit a bound. Every simulation of the fit goes
/// through `hold` when it is enabled (a held log's noise is fitted to what the emulator writes
/// through its static hold, which concentrates a smooth wander's steps into fewer, larger ones).
/// The fit matches the mean over simulated runs of the log's length.
[[nodiscard]] noise::NoiseConfig fit_composite(const EnuSeries& series, const std::array<AxisStats, 3>& real,
                                               std::size_t window, std::vector<std::string>* notes = nullptr,
                                               const StaticHoldOptions& hold = {}, int max_runs = kMaxRefitRuns);
/// Composite time constants and standard deviations stay within these multiples of the log's
/// length and standard deviation (bounded extrapolation).
inline constexpr double kCompositeMaxTauInLogs = 4.0;
inline constexpr double kCompositeMaxSigmaInSd = 5.0;
/// The same with the cgrw walk as the smooth component (composite.smooth = cgrw, the walk's
/// statistics in config.cgrw): the walk's four statistics start at the log's and are scaled
/// (the walk is scale-invariant) until the rounded simulation, jitter and jumps included, has the
/// log's standard deviation, first- and second-difference standard deviations. Deterministic.
[[nodiscard]] noise::NoiseConfig fit_composite_cgrw(const EnuSeries& series, const std::array<AxisStats, 3>& real,
                                                    std::size_t window, std::vector<std::string>* notes = nullptr,
                                                    int max_runs = kMaxRefitRuns);

}  // namespace gpsemu::calibration
