// gpsemu-timing's figures: the statistics of the deviations of a set of epochs (arrival minus
// epoch time plus latency), and the same as JSON for --json.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include <nlohmann/json.hpp>

namespace gpsemu::timing {

/// Deviation statistics of a set of epochs (milliseconds); NaN where there is no epoch.
struct Figures {
  std::size_t epochs = 0;
  double median_ms = NAN, p99_ms = NAN, max_ms = NAN, min_ms = NAN, abs_p99_ms = NAN, abs_max_ms = NAN;
};

/// The p-quantile (0..1) of `v`, linearly interpolated; NaN when `v` is empty.
[[nodiscard]] double percentile(std::vector<double> v, double p);

/// The figures of deviations `dev_ms` (milliseconds).
[[nodiscard]] Figures figures_of(const std::vector<double>& dev_ms);

/// {"epochs", "median_ms", ...}; NaN as null.
[[nodiscard]] nlohmann::json figures_json(const Figures& f);

}  // namespace gpsemu::timing
