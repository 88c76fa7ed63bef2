// Test support: the statistics the noise and end-to-end tests assert on (mean, standard deviation,
// autocorrelation, lagged differences), by the names the tests use, over the one copy in the noise
// library (emulator/model/noise/sample_stats.hpp), which the calibration uses too.
#pragma once

#include <cstddef>
#include <vector>

#include "emulator/model/noise/sample_stats.hpp"

namespace gpsemu::test {

inline double mean_of(const std::vector<double>& x) { return noise::mean(x); }
inline double sd_of(const std::vector<double>& x) { return noise::standard_deviation(x); }
inline double autocorrelation(const std::vector<double>& x, std::size_t lag) { return noise::autocorrelation(x, lag); }
inline double lag1_autocorrelation(const std::vector<double>& x) { return noise::autocorrelation(x, 1); }
/// x[i + lag] - x[i]
inline std::vector<double> differences(const std::vector<double>& x, std::size_t lag) {
  return noise::differences(x, lag);
}

}  // namespace gpsemu::test
