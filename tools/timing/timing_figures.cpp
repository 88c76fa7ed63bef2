#include "tools/timing/timing_figures.hpp"

#include <algorithm>

namespace gpsemu::timing {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const double idx = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(idx));
  const auto hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (v[hi] - v[lo]) * (idx - static_cast<double>(lo));
}

Figures figures_of(const std::vector<double>& dev_ms) {
  Figures f;
  f.epochs = dev_ms.size();
  if (dev_ms.empty()) return f;
  std::vector<double> abs_dev;
  abs_dev.reserve(dev_ms.size());
  for (const double d : dev_ms) abs_dev.push_back(std::abs(d));
  f.median_ms = percentile(dev_ms, 0.5);
  f.p99_ms = percentile(dev_ms, 0.99);
  f.max_ms = *std::max_element(dev_ms.begin(), dev_ms.end());
  f.min_ms = *std::min_element(dev_ms.begin(), dev_ms.end());
  f.abs_p99_ms = percentile(abs_dev, 0.99);
  f.abs_max_ms = *std::max_element(abs_dev.begin(), abs_dev.end());
  return f;
}

nlohmann::json figures_json(const Figures& f) {
  auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"epochs", f.epochs},         {"median_ms", num(f.median_ms)}, {"p99_ms", num(f.p99_ms)},
          {"max_ms", num(f.max_ms)},    {"min_ms", num(f.min_ms)},       {"abs_p99_ms", num(f.abs_p99_ms)},
          {"abs_max_ms", num(f.abs_max_ms)}};
}

}  // namespace gpsemu::timing
