#include "emulator/model/noise/sample_stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gpsemu::noise {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Sum {
  double n = 0, sum = 0;
};

Sum sum_of(std::span<const double> x) {
  Sum s;
  for (double v : x)
    if (!std::isnan(v)) s.n += 1, s.sum += v;
  return s;
}

}  // namespace

double quantile(std::vector<double> x, double q) {
  if (x.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(x.size() - 1));
  std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(k), x.end());
  return x[k];
}

double mean(std::span<const double> x) {
  const Sum s = sum_of(x);
  return s.n > 0 ? s.sum / s.n : kNaN;
}

double standard_deviation(std::span<const double> x) {
  const Sum s = sum_of(x);
  if (s.n < 2) return 0.0;
  const double m = s.sum / s.n;
  double ss = 0.0;
  for (double v : x)
    if (!std::isnan(v)) ss += (v - m) * (v - m);
  return std::sqrt(ss / s.n);
}

double autocorrelation(std::span<const double> x, std::size_t lag) {
  const double m = mean(x);
  double den = 0.0, num = 0.0, pairs = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (std::isnan(x[i])) continue;
    den += (x[i] - m) * (x[i] - m);
    if (i >= lag && !std::isnan(x[i - lag])) num += (x[i] - m) * (x[i - lag] - m), pairs += 1;
  }
  if (den <= 0.0 || pairs == 0.0) return kNaN;
  return num / den;
}

std::vector<double> differences(std::span<const double> x, std::size_t lag) {
  std::vector<double> d;
  if (x.size() > lag) d.reserve(x.size() - lag);
  for (std::size_t i = lag; i < x.size(); ++i) d.push_back(x[i] - x[i - lag]);  // NaN propagates
  return d;
}

}  // namespace gpsemu::noise
