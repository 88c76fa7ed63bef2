// The estimator as the judge of a noise model (`gpsemu judge LOG`): one fixed constant-velocity
// Kalman filter runs on a stationary receiver's log and on simulated runs of every model
// calibrated from that log, and its behaviour is compared. A model that reproduces the real
// error's correlations makes the filter behave as it does on the real receiver.
//
// The filter (fixed, so results are comparable between logs and versions):
//   per horizontal axis, state (position m, velocity m/s), independent axes;
//   transition [[1, dt], [0, 1]], process noise q [[dt^3/3, dt^2/2], [dt^2/2, dt]] with
//   q = kJudgeProcessNoise_m2ps3 (white acceleration), position measured with variance sigma^2,
//   sigma = the receiver's stated horizontal sigma / sqrt 2: median HDOP x kUereM (the emulator's
//   own HDOP convention: HDOP = sigma_h / 0.4 m), or the log's horizontal standard deviation when
//   the log states no HDOP; started at the first fix with velocity 0 (variance sigma^2 and
//   1 (m/s)^2); gaps are predicted across; the first kJudgeBurnIn_s are not scored.
// Scored: the normalised innovation squared (NIS, both axes: chi-square with 2 degrees of
// freedom when the filter's model is right: mean 2, 95th percentile 5.99), the lag-1
// autocorrelation of the normalised innovations (0 when right), and the rms horizontal distance of
// the filtered position from the series' mean position.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "emulator/calibration/calibrate.hpp"
#include "emulator/model/receiver.hpp"

namespace gpsemu::calibration {

inline constexpr double kJudgeProcessNoise_m2ps3 = 1e-4;
inline constexpr double kJudgeBurnIn_s = 10.0;

/// What the filter did on one series (or the mean over runs).
struct FilterScore {
  double nis_mean = 0.0;
  double nis_p95 = 0.0;
  double innov_rho1 = 0.0;   ///< lag-1 autocorrelation of the normalised innovations (mean of the axes)
  double pos_err_m = 0.0;    ///< rms horizontal distance of the estimate from the series' mean
  std::vector<double> nis;   ///< per scored epoch (empty for means over runs)
};

/// Runs the filter on east and north (metres, NaN = no fix) at `rate_hz`, measurement standard
/// deviation `sigma_m` per axis, process noise `q_m2ps3`.
[[nodiscard]] FilterScore run_cv_filter(const std::vector<double>& east_m, const std::vector<double>& north_m,
                                        double rate_hz, double sigma_m, double q_m2ps3 = kJudgeProcessNoise_m2ps3);

/// The per-axis measurement sigma the filter uses for a log (see above).
[[nodiscard]] double stated_sigma_m(const ReceiverLog& log, const Calibration& c);

struct Judgement {
  double sigma_m = 0.0;                         ///< measurement sigma per axis used
  FilterScore real;                             ///< on the log
  /// The median over the runs (each a window of the log's length), by model label; the distance is of these.
  std::map<std::string, FilterScore> models;
  std::map<std::string, std::array<FilterScore, 2>> spread;  ///< 10th and 90th percentiles over the runs
  std::map<std::string, std::vector<std::vector<double>>> model_nis;  ///< each run's NIS
  std::map<std::string, double> distance;       ///< how far each model's filter behaviour is from real's
  std::string best;                             ///< the model with the least distance
};

/// The filter on the calibrated log and on `runs` simulated runs (seeds seed, seed + 1, ...) of each
/// calibrated model. distance = |ln(nis_mean ratio)| + |ln(nis_p95 ratio)| + |rho1 difference| +
/// |ln(pos_err ratio)|.
[[nodiscard]] Judgement judge(const Calibration& c, double sigma_m, int runs, std::uint64_t seed);

/// The table printed by `gpsemu judge`.
[[nodiscard]] std::string judgement_table(const Judgement& j);

/// When the judge's best model is not the statistics' (c.best), why: which term of the judge's
/// distance the statistics' best loses on, and which statistics the judge's best misses. Empty
/// when they agree.
[[nodiscard]] std::string disagreement(const Judgement& j, const Calibration& c);
/// {"real": {...}, "models": {NAME: {...}}, "best": NAME, "sigma_m": ...}.
[[nodiscard]] std::string judgement_json(const Judgement& j);
/// Writes DIR/judge_nis.csv (source,run,nis per scored epoch) and DIR/judge_summary.csv (one row
/// per source). Throws std::runtime_error naming the file when it cannot be written.
void write_judgement_csv(const Judgement& j, const std::string& dir);

}  // namespace gpsemu::calibration
