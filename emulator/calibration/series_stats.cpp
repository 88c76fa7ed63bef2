#include "emulator/calibration/series_stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "emulator/model/noise/sample_stats.hpp"

namespace gpsemu::calibration {
namespace {

// max - min of the samples present.
struct Range {
  double n = 0, lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (std::isnan(v)) return;
    n += 1, lo = std::min(lo, v), hi = std::max(hi, v);
  }
  [[nodiscard]] double range() const { return n > 0 ? hi - lo : 0.0; }
};

std::vector<double> fill_gaps(std::span<const double> x) {
  std::vector<double> y(x.begin(), x.end());
  std::size_t prev = y.size();
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (std::isnan(y[i])) continue;
    if (prev < y.size() && i > prev + 1) {
      for (std::size_t j = prev + 1; j < i; ++j)
        y[j] = y[prev] + (y[i] - y[prev]) * static_cast<double>(j - prev) / static_cast<double>(i - prev);
    }
    prev = i;
  }
  // Leading or trailing gaps (not produced by to_enu_series): hold the nearest fix.
  auto first = std::find_if(y.begin(), y.end(), [](double v) { return !std::isnan(v); });
  if (first == y.end()) return y;
  std::fill(y.begin(), first, *first);
  for (std::size_t i = 1; i < y.size(); ++i)
    if (std::isnan(y[i])) y[i] = y[i - 1];
  return y;
}

std::optional<double> allan_deviation(const std::vector<double>& y, std::size_t m) {
  const std::size_t n = y.size();
  if (m == 0 || n < 3 * m) return std::nullopt;
  std::vector<double> prefix(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + y[i];
  const auto avg = [&](std::size_t j) { return (prefix[j + m] - prefix[j]) / static_cast<double>(m); };
  double ss = 0.0;
  const std::size_t terms = n - 2 * m + 1;
  for (std::size_t j = 0; j < terms; ++j) {
    const double d = avg(j + m) - avg(j);
    ss += d * d;
  }
  return std::sqrt(ss / (2.0 * static_cast<double>(terms)));
}

}  // namespace

noise::CgrwAxis measure_cgrw_with_gaps(std::span<const double> x) {
  Range p, d1, d2;
  std::vector<double> second;
  for (std::size_t i = 0; i < x.size(); ++i) {
    p.add(x[i]);
    if (i >= 1) d1.add(x[i] - x[i - 1]);
    if (i >= 2) {
      const double v = (x[i] - x[i - 1]) - (x[i - 1] - x[i - 2]);
      d2.add(v);
      second.push_back(v);
    }
  }
  return {p.range(), d1.range(), d2.range(), noise::standard_deviation(second)};
}

AxisStats measure_axis(std::span<const double> x, double rate_hz, std::size_t window_samples) {
  AxisStats s;
  Range m;
  for (double v : x) m.add(v);
  s.range_m = m.range();
  s.sd_m = noise::standard_deviation(x);
  const std::vector<double> d1 = noise::differences(x);
  s.d1_sd_m = noise::standard_deviation(d1);
  s.d2_sd_m = noise::standard_deviation(noise::differences(d1));
  for (std::size_t i = 0; i < kLags.size(); ++i) s.acf[i] = noise::autocorrelation(x, kLags[i]);
  for (std::size_t i = 0; i < kAcfTimes_s.size(); ++i) {
    const double lag = kAcfTimes_s[i] * rate_hz;
    if (std::abs(lag - std::round(lag)) < 1e-9 && lag >= 1.0 && 3.0 * lag <= static_cast<double>(x.size()))
      s.acf_s[i] = noise::autocorrelation(x, static_cast<std::size_t>(std::llround(lag)));
  }
  const std::vector<double> filled = fill_gaps(x);
  for (std::size_t i = 0; i < kAllanTimes_s.size(); ++i) {
    const double samples = kAllanTimes_s[i] * rate_hz;
    if (std::abs(samples - std::round(samples)) < 1e-9)
      s.allan_m[i] = allan_deviation(filled, static_cast<std::size_t>(std::llround(samples)));
  }
  const std::size_t w = std::clamp<std::size_t>(window_samples, 3, std::max<std::size_t>(x.size(), 3));
  const std::size_t windows = std::max<std::size_t>(x.size() / w, 1);
  noise::CgrwAxis sum{0, 0, 0, 0};
  for (std::size_t k = 0; k < windows; ++k) {
    const noise::CgrwAxis c = measure_cgrw_with_gaps(x.subspan(k * w, std::min(w, x.size() - k * w)));
    sum.width_m += c.width_m, sum.width_d1_m += c.width_d1_m, sum.width_d2_m += c.width_d2_m,
        sum.sigma_d2_m += c.sigma_d2_m;
  }
  const double k = static_cast<double>(windows);
  s.cgrw = {sum.width_m / k, sum.width_d1_m / k, sum.width_d2_m / k, sum.sigma_d2_m / k};
  return s;
}

const std::vector<StatDef>& stat_defs() {
  using O = std::optional<double>;
  static const std::vector<StatDef> defs{
      {"max-min (m)", [](const AxisStats& s) -> O { return s.range_m; },
       [](const AxisStats& s) -> O { return s.range_m; }},
      {"std (m)", [](const AxisStats& s) -> O { return s.sd_m; },
       [](const AxisStats& s) -> O { return s.sd_m; }},
      {"d1 std (m)", [](const AxisStats& s) -> O { return s.d1_sd_m; },
       [](const AxisStats& s) -> O { return s.d1_sd_m; }},
      {"d2 std (m)", [](const AxisStats& s) -> O { return s.d2_sd_m; },
       [](const AxisStats& s) -> O { return s.d2_sd_m; }},
      {"lag-1 acf", [](const AxisStats& s) -> O { return 1.0 - s.acf[0]; },
       [](const AxisStats& s) -> O { return s.acf[0]; }},
      {"lag-10 acf", [](const AxisStats& s) -> O { return 1.0 - s.acf[1]; },
       [](const AxisStats& s) -> O { return s.acf[1]; }},
      {"acf 10 s", [](const AxisStats& s) -> O { return s.acf_s[0] ? O(1.0 - *s.acf_s[0]) : std::nullopt; },
       [](const AxisStats& s) -> O { return s.acf_s[0]; }},
      {"acf 30 s", [](const AxisStats& s) -> O { return s.acf_s[1] ? O(1.0 - *s.acf_s[1]) : std::nullopt; },
       [](const AxisStats& s) -> O { return s.acf_s[1]; }},
      {"adev 1 s (m)", [](const AxisStats& s) { return s.allan_m[0]; },
       [](const AxisStats& s) { return s.allan_m[0]; }},
      {"adev 10 s (m)", [](const AxisStats& s) { return s.allan_m[1]; },
       [](const AxisStats& s) { return s.allan_m[1]; }},
      {"adev 100 s (m)", [](const AxisStats& s) { return s.allan_m[2]; },
       [](const AxisStats& s) { return s.allan_m[2]; }},
  };
  return defs;
}

AxisStats mean_stats(const std::vector<AxisStats>& runs) {
  AxisStats m;
  if (runs.empty()) return m;
  const double n = static_cast<double>(runs.size());
  m.range_m = m.sd_m = m.d1_sd_m = m.d2_sd_m = 0.0;
  m.cgrw = {0, 0, 0, 0};
  std::array<double, 3> allan_sum{};
  std::array<int, 3> allan_count{};
  std::array<double, 2> acf_sum{};
  std::array<int, 2> acf_count{};
  for (const AxisStats& r : runs) {
    m.range_m += r.range_m / n, m.sd_m += r.sd_m / n, m.d1_sd_m += r.d1_sd_m / n,
        m.d2_sd_m += r.d2_sd_m / n;
    for (std::size_t i = 0; i < m.acf.size(); ++i) m.acf[i] += r.acf[i] / n;
    for (std::size_t i = 0; i < 3; ++i)
      if (r.allan_m[i]) allan_sum[i] += *r.allan_m[i], ++allan_count[i];
    for (std::size_t i = 0; i < 2; ++i)
      if (r.acf_s[i]) acf_sum[i] += *r.acf_s[i], ++acf_count[i];
    m.cgrw.width_m += r.cgrw.width_m / n, m.cgrw.width_d1_m += r.cgrw.width_d1_m / n,
        m.cgrw.width_d2_m += r.cgrw.width_d2_m / n, m.cgrw.sigma_d2_m += r.cgrw.sigma_d2_m / n;
  }
  for (std::size_t i = 0; i < 3; ++i)
    if (allan_count[i] == static_cast<int>(runs.size())) m.allan_m[i] = allan_sum[i] / n;
  for (std::size_t i = 0; i < 2; ++i)
    if (acf_count[i] == static_cast<int>(runs.size())) m.acf_s[i] = acf_sum[i] / n;
  return m;
}

AxisStats quantile_stats(const std::vector<AxisStats>& runs, double q) {
  AxisStats m;
  if (runs.empty()) return m;
  const auto pick = [&](auto get) {
    std::vector<double> v;
    for (const AxisStats& r : runs) v.push_back(get(r));
    return noise::quantile(std::move(v), q);
  };
  m.range_m = pick([](const AxisStats& r) { return r.range_m; });
  m.sd_m = pick([](const AxisStats& r) { return r.sd_m; });
  m.d1_sd_m = pick([](const AxisStats& r) { return r.d1_sd_m; });
  m.d2_sd_m = pick([](const AxisStats& r) { return r.d2_sd_m; });
  for (std::size_t i = 0; i < m.acf.size(); ++i) m.acf[i] = pick([i](const AxisStats& r) { return r.acf[i]; });
  const auto all = [&](auto has) { return std::all_of(runs.begin(), runs.end(), has); };
  for (std::size_t i = 0; i < m.allan_m.size(); ++i)
    if (all([i](const AxisStats& r) { return r.allan_m[i].has_value(); }))
      m.allan_m[i] = pick([i](const AxisStats& r) { return *r.allan_m[i]; });
  for (std::size_t i = 0; i < m.acf_s.size(); ++i)
    if (all([i](const AxisStats& r) { return r.acf_s[i].has_value(); }))
      m.acf_s[i] = pick([i](const AxisStats& r) { return *r.acf_s[i]; });
  m.cgrw.width_m = pick([](const AxisStats& r) { return r.cgrw.width_m; });
  m.cgrw.width_d1_m = pick([](const AxisStats& r) { return r.cgrw.width_d1_m; });
  m.cgrw.width_d2_m = pick([](const AxisStats& r) { return r.cgrw.width_d2_m; });
  m.cgrw.sigma_d2_m = pick([](const AxisStats& r) { return r.cgrw.sigma_d2_m; });
  return m;
}

double score(const std::array<AxisStats, 3>& real, const std::array<AxisStats, 3>& model) {
  constexpr double kFloor = 1e-6;
  double sum = 0.0;
  int count = 0;
  for (std::size_t a = 0; a < 3; ++a) {
    for (const StatDef& d : stat_defs()) {
      const auto r = d.get(real[a]);
      const auto m = d.get(model[a]);
      if (!r || !m || std::isnan(*r) || std::isnan(*m)) continue;
      sum += std::abs(std::log(std::max(*m, kFloor) / std::max(*r, kFloor)));
      ++count;
    }
  }
  return count > 0 ? sum / count : std::numeric_limits<double>::infinity();
}

}  // namespace gpsemu::calibration
