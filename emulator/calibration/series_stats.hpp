// Statistics of one axis of a stationary receiver's position series, real or simulated, computed
// the same way for both so they can be put side by side: spread, first and second differences,
// autocorrelation, Allan deviation, the report's four cgrw statistics; and the comparison score.
// Samples are on an epoch grid; NaN marks an epoch without a fix (a difference or a lagged pair
// that touches one is left out).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "emulator/model/noise/noise_model.hpp"

namespace gpsemu::calibration {

/// Allan deviation averaging times (seconds).
inline constexpr std::array<double, 3> kAllanTimes_s{1.0, 10.0, 100.0};
/// Autocorrelation lags (samples of the grid).
inline constexpr std::array<std::size_t, 2> kLags{1, 10};
/// Autocorrelation lags in time (seconds): the correlation a receiver keeps beyond its smooth part.
inline constexpr std::array<double, 2> kAcfTimes_s{10.0, 30.0};

struct AxisStats {
  double range_m = 0;     ///< max - min
  double sd_m = 0;        ///< standard deviation (population)
  double d1_sd_m = 0;     ///< standard deviation of the first difference (metres per sample)
  double d2_sd_m = 0;     ///< standard deviation of the second difference (metres per sample^2)
  std::array<double, 2> acf{};  ///< autocorrelation at kLags
  /// Autocorrelation at kAcfTimes_s; empty when the lag is not a whole number of samples or the
  /// series is shorter than 3 lags.
  std::array<std::optional<double>, 2> acf_s{};
  /// Overlapping Allan deviation of the position at kAllanTimes_s (metres); empty when the
  /// series is shorter than 3 averaging times or the time is not a whole number of samples.
  std::array<std::optional<double>, 3> allan_m{};
  noise::CgrwAxis cgrw;   ///< the report's four statistics (mean over windows, see measure)
};

/// The statistics of `x` at `rate_hz`; the cgrw statistics are the mean over consecutive windows
/// of `window_samples` (gaps count as in the rest: a window's widths are over its fixes).
/// Allan deviation uses the series with gaps filled by linear interpolation.
[[nodiscard]] AxisStats measure_axis(std::span<const double> x, double rate_hz,
                                     std::size_t window_samples);

/// The report's four statistics of one window with NaN gaps (equal to noise::measure_cgrw_axis
/// when there is none).
[[nodiscard]] noise::CgrwAxis measure_cgrw_with_gaps(std::span<const double> x);

/// One named statistic of AxisStats, as the score and the tables see it.
struct StatDef {
  std::string_view name;
  /// The value compared in ratio (1 - rho for autocorrelations: how far from 1), or nullopt.
  std::optional<double> (*get)(const AxisStats&);
  std::optional<double> (*show)(const AxisStats&);  ///< the value printed
};
/// range, sd, d1 sd, d2 sd, lag-1 and lag-10 autocorrelation, autocorrelation at 10 and 30 s,
/// Allan deviation at 1, 10, 100 s.
[[nodiscard]] const std::vector<StatDef>& stat_defs();

/// Mean of each statistic over several runs (missing ones stay missing).
[[nodiscard]] AxisStats mean_stats(const std::vector<AxisStats>& runs);

/// The `q` quantile (0..1; 0.5 the median, by the nearest rank below) of each statistic over
/// several runs, each statistic on its own (missing ones stay missing): what a typical run of the
/// log's length looks like, and how far one can be.
[[nodiscard]] AxisStats quantile_stats(const std::vector<AxisStats>& runs, double q);

/// The comparison score of a model against the real receiver: the mean, over the three axes and
/// every statistic of stat_defs() both have, of |ln(model / real)| (values floored at 1e-6).
/// 0 is a perfect match; 0.1 is about 10% off on average, 0.69 a factor 2.
[[nodiscard]] double score(const std::array<AxisStats, 3>& real, const std::array<AxisStats, 3>& model);

}  // namespace gpsemu::calibration
