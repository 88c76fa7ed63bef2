#include "emulator/model/noise/cgrw_fit.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "emulator/model/noise/rng.hpp"

namespace gpsemu::noise {
namespace {

using Vec4 = std::array<double, 4>;  // p_max, v_max, a_max, sigma  or  W, W1, W2, S2

constexpr std::size_t kMaxFitWindows = 32;
constexpr std::size_t kMinFitWindows = 8;
constexpr std::size_t kFitStepBudget = 320000;  // samples in all windows, when windows are long
constexpr int kMaxIterations = 40;
constexpr std::uint64_t kFitSeed = 0x6370727766697421ULL;  // fixed: the fit is deterministic
constexpr Vec4 kWeights{4.0, 1.0, 1.0, 1.0};               // the width is the knob: match it first
constexpr double kMinAmaxPerSigma = 0.05;                  // below: a is always +-a_max
constexpr double kMaxAmaxPerSigma = 50.0;                  // above: the clamp never acts
constexpr double kTolerance = 0.02;                        // |log ratio| of every statistic
constexpr double kMinGain = 0.02;                          // relative cost decrease to go on

std::string field(std::string_view name, const char* member) {
  return std::string(name) + "." + member;
}

Vec4 to_vec(const CgrwAxis& s) { return {s.width_m, s.width_d1_m, s.width_d2_m, s.sigma_d2_m}; }
CgrwAxis to_axis(const Vec4& s) { return {s[0], s[1], s[2], s[3]}; }
CgrwInternal to_internal(const Vec4& log_q) {
  return {std::exp(log_q[0]), std::exp(log_q[1]), std::exp(log_q[2]), std::exp(log_q[3])};
}

// Common random numbers: every evaluation of the objective walks on the same normal draws.
class FitSimulation {
 public:
  FitSimulation(std::size_t burn_in, std::size_t window)
      : burn_in_(burn_in), window_(window),
        windows_(std::clamp(kFitStepBudget / window, kMinFitWindows, kMaxFitWindows)),
        normals_(burn_in + window * windows_), paths_(kMaxWalks * window) {
    Rng rng(kFitSeed, 0);
    for (double& x : normals_) x = rng.normal();
  }

  // Mean statistics over the windows for the internal parameters exp(log_q).
  Vec4 statistics(const Vec4& log_q) { return statistics<1>({log_q})[0]; }

  // The same for N parameter sets at once, each on the same numbers and with the same arithmetic
  // as alone (so bit for bit the same results): the N walks step side by side, and their chains of
  // dependent operations (a division, clamps and additions a step) overlap in the CPU.
  static constexpr std::size_t kMaxWalks = 4;  // the Jacobian's four
  template <std::size_t N>
  std::array<Vec4, N> statistics(const std::array<Vec4, N>& log_q) {
    static_assert(N <= kMaxWalks);
    std::array<CgrwInternal, N> k{};
    std::array<double, N> p{}, v{};
    for (std::size_t m = 0; m < N; ++m) k[m] = to_internal(log_q[m]);
    std::size_t i = 0;
    for (; i < burn_in_; ++i)
      for (std::size_t m = 0; m < N; ++m) cgrw_step(k[m], normals_[i], p[m], v[m]);
    std::array<Vec4, N> sum{};
    for (std::size_t w = 0; w < windows_; ++w) {
      for (std::size_t x = 0; x < window_; ++x, ++i)
        for (std::size_t m = 0; m < N; ++m) {
          cgrw_step(k[m], normals_[i], p[m], v[m]);
          paths_[m * window_ + x] = p[m];
        }
      for (std::size_t m = 0; m < N; ++m) {
        const Vec4 s = to_vec(measure_cgrw_axis(std::span<const double>(paths_).subspan(m * window_, window_)));
        for (int j = 0; j < 4; ++j) sum[m][j] += s[j];
      }
    }
    for (Vec4& x : sum)
      for (double& y : x) y /= static_cast<double>(windows_);
    return sum;
  }

 private:
  std::size_t burn_in_;
  std::size_t window_;
  std::size_t windows_;
  std::vector<double> normals_;
  std::vector<double> paths_;  // the windows of the walks stepped together, one after the other
};

// Solves A x = b (4x4) by Gaussian elimination with partial pivoting; false if singular.
bool solve4(std::array<Vec4, 4> a, Vec4 b, Vec4& x) {
  for (int c = 0; c < 4; ++c) {
    int piv = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
    if (std::abs(a[piv][c]) < 1e-300) return false;
    std::swap(a[c], a[piv]);
    std::swap(b[c], b[piv]);
    for (int r = c + 1; r < 4; ++r) {
      const double f = a[r][c] / a[c][c];
      for (int j = c; j < 4; ++j) a[r][j] -= f * a[c][j];
      b[r] -= f * b[c];
    }
  }
  for (int r = 3; r >= 0; --r) {
    double s = b[r];
    for (int j = r + 1; j < 4; ++j) s -= a[r][j] * x[j];
    x[r] = s / a[r][r];
  }
  return true;
}

Vec4 log_residual(const Vec4& measured, const Vec4& log_target) {
  Vec4 r{};
  for (int j = 0; j < 4; ++j) r[j] = std::log(std::max(measured[j], 1e-300)) - log_target[j];
  return r;
}
double cost(const Vec4& r) {
  double c = 0.0;
  for (int j = 0; j < 4; ++j) c += kWeights[j] * r[j] * r[j];
  return c;
}
void keep_amax_in_range(Vec4& log_q) {
  log_q[2] = std::clamp(log_q[2], log_q[3] + std::log(kMinAmaxPerSigma),
                        log_q[3] + std::log(kMaxAmaxPerSigma));
}

// The fit proper, for a target of unit width.
CgrwFit fit_unit(const Vec4& target, std::size_t window) {
  // Initial guess from the undamped oscillator the walk is: velocity amplitude v_max, angular
  // frequency omega = sqrt(sigma / p_max), position amplitude v_max / omega.
  const double omega = target[1] / target[0];
  Vec4 q{0.0, std::log(target[1] / 2), std::log(target[2] / 2), std::log(target[3])};
  q[0] = std::log(target[3] / (omega * omega));
  keep_amax_in_range(q);

  FitSimulation sim(cgrw_burn_in_steps(to_internal(q), static_cast<double>(window)), window);
  Vec4 log_target{};
  for (int j = 0; j < 4; ++j) log_target[j] = std::log(target[j]);
  Vec4 f = sim.statistics(q);
  Vec4 r = log_residual(f, log_target);
  double lambda = 1e-2;
  int it = 0;
  for (; it < kMaxIterations; ++it) {
    bool done = true;
    for (double x : r) done = done && std::abs(x) < kTolerance;
    if (done) break;
    // Finite-difference Jacobian of the log statistics in the log parameters.
    constexpr double h = 0.05;
    std::array<Vec4, 4> jac{};  // jac[i][j] = d log stat i / d log param j
    std::array<Vec4, 4> qs{q, q, q, q};
    for (int j = 0; j < 4; ++j) qs[j][j] += h;
    const std::array<Vec4, 4> fs = sim.statistics<4>(qs);
    for (int j = 0; j < 4; ++j) {
      const Vec4 rj = log_residual(fs[j], log_target);
      for (int i = 0; i < 4; ++i) jac[i][j] = (rj[i] - r[i]) / h;
    }
    std::array<Vec4, 4> jtj{};
    Vec4 grad{};
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b)
        for (int i = 0; i < 4; ++i) jtj[a][b] += jac[i][a] * kWeights[i] * jac[i][b];
      for (int i = 0; i < 4; ++i) grad[a] -= jac[i][a] * kWeights[i] * r[i];
    }
    const double c0 = cost(r);
    bool improved = false;
    while (!improved && lambda < 1e6) {
      std::array<Vec4, 4> damped = jtj;
      for (int a = 0; a < 4; ++a) damped[a][a] += lambda * (jtj[a][a] + 1e-9);
      Vec4 step{};
      if (solve4(damped, grad, step)) {
        Vec4 qn = q;
        for (int a = 0; a < 4; ++a) qn[a] += std::clamp(step[a], -1.0, 1.0);
        keep_amax_in_range(qn);
        const Vec4 fn = sim.statistics(qn);
        const Vec4 rn = log_residual(fn, log_target);
        if (cost(rn) < c0) {
          q = qn, f = fn, r = rn;
          lambda = std::max(lambda / 3.0, 1e-6);
          improved = true;
          break;
        }
      }
      lambda *= 4.0;
    }
    // No descent left, or too little to matter: the best compromise this model allows.
    if (!improved || cost(r) > (1.0 - kMinGain) * c0) break;
  }
  CgrwFit fit;
  fit.internal = to_internal(q);
  fit.achieved = to_axis(f);
  fit.iterations = it;
  for (int j = 0; j < 4; ++j)
    fit.worst_ratio = std::max(fit.worst_ratio, std::exp(std::abs(r[j])));
  return fit;
}

}  // namespace

CgrwFit fit_cgrw_axis(const CgrwAxis& target, double window_samples, std::string_view name,
                      double max_ratio) {
  validate_cgrw_axis(target, name);
  if (cgrw_axis_off(target)) {
    CgrwFit off;
    off.internal = {1.0, 0.0, 0.0, 0.0};
    off.achieved = target;
    return off;
  }
  if (!(window_samples >= kCgrwMinWindowSamples && window_samples <= kCgrwMaxWindowSamples)) {
    std::ostringstream os;
    os << name << ": window_samples (window_s x rate_hz) must be " << kCgrwMinWindowSamples
       << " to " << kCgrwMaxWindowSamples << " (got " << window_samples << ")";
    throw std::invalid_argument(os.str());
  }
  const std::size_t window = static_cast<std::size_t>(std::llround(window_samples));
  const double w = target.width_m;
  const Vec4 unit{1.0, target.width_d1_m / w, target.width_d2_m / w, target.sigma_d2_m / w};

  // Scale invariance: fit the shape once at unit width, cache it, scale by the width.
  static std::mutex mutex;
  static std::map<std::tuple<double, double, double, std::size_t>, CgrwFit> cache;
  const auto key = std::make_tuple(unit[1], unit[2], unit[3], window);
  CgrwFit fit;
  {
    std::lock_guard lock(mutex);
    if (auto it = cache.find(key); it != cache.end()) {
      fit = it->second;
      fit.iterations = 0;
    } else {
      fit = fit_unit(unit, window);
      if (cache.size() >= 256) cache.clear();
      cache.emplace(key, fit);
    }
  }
  fit.internal = {fit.internal.p_max_m * w, fit.internal.v_max_m * w, fit.internal.a_max_m * w,
                  fit.internal.sigma_m * w};
  fit.achieved = {fit.achieved.width_m * w, fit.achieved.width_d1_m * w,
                  fit.achieved.width_d2_m * w, fit.achieved.sigma_d2_m * w};
  if (fit.worst_ratio > max_ratio) {
    const Vec4 want = to_vec(target), got = to_vec(fit.achieved);
    const char* names[] = {"width_m", "width_d1_m", "width_d2_m", "sigma_d2_m"};
    std::ostringstream os;
    os << name << ": the cgrw walk cannot reproduce these statistics together (best fit off by"
       << " a factor " << fit.worst_ratio << "):";
    for (int j = 0; j < 4; ++j)
      os << " " << field(name, names[j]) << " " << want[j] << " -> " << got[j];
    throw std::invalid_argument(os.str());
  }
  return fit;
}

CgrwAxis nudge_cgrw_axis(const CgrwAxis& s, bool* changed) {
  constexpr double kMargin = 0.99;
  CgrwAxis n = s;
  const auto ok = [](double x) { return x > 0.0 && std::isfinite(x); };
  if (!ok(n.width_m)) {
    n = {0.0, 0.0, 0.0, 0.0};
  } else {
    // A missing derivative statistic gets a tiny share of the width (the axis moves rarely).
    if (!ok(n.width_d1_m)) n.width_d1_m = 1e-3 * n.width_m;
    if (!ok(n.width_d2_m)) n.width_d2_m = n.width_d1_m;
    if (!ok(n.sigma_d2_m)) n.sigma_d2_m = 0.25 * n.width_d2_m;
    n.width_d1_m = std::min(n.width_d1_m, 2.0 * kMargin * n.width_m);
    n.width_d2_m = std::min(n.width_d2_m, 2.0 * kMargin * n.width_d1_m);
    n.sigma_d2_m = std::min(n.sigma_d2_m, 0.5 * kMargin * n.width_d2_m);
  }
  if (changed)
    *changed = n.width_m != s.width_m || n.width_d1_m != s.width_d1_m || n.width_d2_m != s.width_d2_m ||
               n.sigma_d2_m != s.sigma_d2_m;
  return n;
}

std::size_t cgrw_burn_in_steps(const CgrwInternal& k, double window_samples) {
  if (!(k.sigma_m > 0.0)) return 16;  // an axis that is off
  const double v_per_sigma = k.v_max_m / k.sigma_m;
  const double period = 2.0 * std::numbers::pi * std::sqrt(k.p_max_m / k.sigma_m);
  double steps = std::max(window_samples, 4.0 * v_per_sigma * v_per_sigma + 4.0 * period);
  steps = std::clamp(steps, 16.0, 100000.0);
  return static_cast<std::size_t>(std::ceil(steps));
}

}  // namespace gpsemu::noise
