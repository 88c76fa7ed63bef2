// Plain statistics of a sampled series: mean, population standard deviation, autocorrelation at a
// lag, a quantile and lagged differences. NaN marks a missing sample (an epoch without a fix) and is left out,
// as is every difference or lagged pair that touches one. One copy for the calibration's series
// statistics (emulator/calibration/series_stats) and the noise models' tests.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace gpsemu::noise {

/// Mean of the samples present (NaN when there is none).
[[nodiscard]] double mean(std::span<const double> x);

/// Population standard deviation of the samples present, two passes (0 with fewer than two).
[[nodiscard]] double standard_deviation(std::span<const double> x);

/// The usual (biased) autocorrelation estimate at `lag` samples: the sum over the lagged pairs
/// both present of the products of deviations from the mean, over the sum of squared deviations.
/// NaN when there is no such pair or the series is constant.
[[nodiscard]] double autocorrelation(std::span<const double> x, std::size_t lag);

/// The `q` quantile (0..1) of `x` by the nearest rank below (index floor(q (n - 1))); 0 when empty.
[[nodiscard]] double quantile(std::vector<double> x, double q);

/// x[i + lag] - x[i] for every i (NaN where either sample is missing).
[[nodiscard]] std::vector<double> differences(std::span<const double> x, std::size_t lag = 1);

}  // namespace gpsemu::noise
