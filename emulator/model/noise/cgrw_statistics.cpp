// The report's four statistics of a series, and the checks that four statistics are possible.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "emulator/model/noise/cgrw_fit.hpp"

namespace gpsemu::noise {
namespace {

std::string field(std::string_view name, const char* member) {
  return std::string(name) + "." + member;
}

void require_positive(double x, std::string_view name, const char* member) {
  if (!(x > 0.0) || !std::isfinite(x)) {
    std::ostringstream os;
    os << field(name, member) << " must be positive and finite (got " << x << ")";
    throw std::invalid_argument(os.str());
  }
}

}  // namespace

CgrwAxis measure_cgrw_axis(std::span<const double> samples) {
  const std::size_t n = samples.size();
  if (n < 3) throw std::invalid_argument("measure_cgrw_axis needs at least 3 samples");
  const auto d2_at = [&](std::size_t i) {  // second difference ending at sample i >= 2
    return (samples[i] - samples[i - 1]) - (samples[i - 1] - samples[i - 2]);
  };
  double lo = std::min(samples[0], samples[1]), hi = std::max(samples[0], samples[1]);
  double lo1 = samples[1] - samples[0], hi1 = lo1;
  double lo2 = d2_at(2), hi2 = lo2, sum2 = 0.0;
  for (std::size_t i = 2; i < n; ++i) {
    lo = std::min(lo, samples[i]);
    hi = std::max(hi, samples[i]);
    const double d1 = samples[i] - samples[i - 1];
    lo1 = std::min(lo1, d1);
    hi1 = std::max(hi1, d1);
    const double d2 = d2_at(i);
    lo2 = std::min(lo2, d2);
    hi2 = std::max(hi2, d2);
    sum2 += d2;
  }
  const double count2 = static_cast<double>(n - 2);
  const double mean2 = sum2 / count2;
  double ss2 = 0.0;  // second pass: no cancellation
  for (std::size_t i = 2; i < n; ++i) ss2 += (d2_at(i) - mean2) * (d2_at(i) - mean2);
  return {hi - lo, hi1 - lo1, hi2 - lo2, std::sqrt(ss2 / count2)};
}

CgrwAxis mean_cgrw_statistics(std::span<const double> samples, std::size_t window_samples) {
  if (window_samples < 3 || samples.size() < window_samples)
    throw std::invalid_argument("mean_cgrw_statistics needs one whole window of at least 3 samples");
  const std::size_t n = samples.size() / window_samples;
  CgrwAxis sum{0.0, 0.0, 0.0, 0.0};
  for (std::size_t w = 0; w < n; ++w) {
    const CgrwAxis s = measure_cgrw_axis(samples.subspan(w * window_samples, window_samples));
    sum.width_m += s.width_m;
    sum.width_d1_m += s.width_d1_m;
    sum.width_d2_m += s.width_d2_m;
    sum.sigma_d2_m += s.sigma_d2_m;
  }
  const double k = static_cast<double>(n);
  return {sum.width_m / k, sum.width_d1_m / k, sum.width_d2_m / k, sum.sigma_d2_m / k};
}

void validate_cgrw_axis(const CgrwAxis& s, std::string_view name) {
  if (cgrw_axis_off(s)) return;  // all four 0: no noise on this axis
  require_positive(s.width_m, name, "width_m");
  require_positive(s.width_d1_m, name, "width_d1_m");
  require_positive(s.width_d2_m, name, "width_d2_m");
  require_positive(s.sigma_d2_m, name, "sigma_d2_m");
  std::ostringstream os;
  if (s.width_d1_m > 2.0 * s.width_m) {
    os << field(name, "width_d1_m") << " (" << s.width_d1_m << ") cannot exceed 2 x "
       << field(name, "width_m") << " (" << s.width_m << "): no step leaves the position range";
  } else if (s.width_d2_m > 2.0 * s.width_d1_m) {
    os << field(name, "width_d2_m") << " (" << s.width_d2_m << ") cannot exceed 2 x "
       << field(name, "width_d1_m") << " (" << s.width_d1_m << ")";
  } else if (s.width_d2_m < 2.0 * s.sigma_d2_m) {
    os << field(name, "sigma_d2_m") << " (" << s.sigma_d2_m << ") cannot exceed half of "
       << field(name, "width_d2_m") << " (" << s.width_d2_m << "): a spread cannot exceed half"
       << " its range";
  }
  if (!os.str().empty()) throw std::invalid_argument(os.str());
}

}  // namespace gpsemu::noise
