// The composite model's fit (model_fits.hpp: fit_composite): jumps, the smooth part and white
// jitter refitted together, and the slow part chosen on the autocorrelation at 10 and 30 s.
#include "emulator/calibration/model_fits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/calibration/calibrate.hpp"
#include "emulator/model/noise/cgrw_fit.hpp"
#include "emulator/model/noise/cgrw_model.hpp"
#include "emulator/model/noise/gauss_markov_model.hpp"


namespace gpsemu::calibration {
namespace {

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The jumps of one axis: first differences beyond 5 robust standard deviations (1.4826 MAD) and
// two quanta of the log's resolution.
noise::CompositeAxis find_jumps(const std::vector<double>& x, double rate_hz, double quantum_m) {
  std::vector<double> d1;
  for (std::size_t k = 1; k < x.size(); ++k)
    if (!std::isnan(x[k]) && !std::isnan(x[k - 1])) d1.push_back(x[k] - x[k - 1]);
  noise::CompositeAxis a;
  if (d1.size() < 8) return a;
  const double med = median_of(d1);
  std::vector<double> dev;
  for (double d : d1) dev.push_back(std::abs(d - med));
  const double threshold = std::max({5.0 * 1.4826 * median_of(dev), 2.0 * quantum_m, 1e-4});
  double count = 0.0, sum2 = 0.0;
  for (double d : d1)
    if (std::abs(d - med) > threshold) count += 1.0, sum2 += d * d;
  if (count == 0.0) return a;
  a.jump_rate_hz = count * rate_hz / static_cast<double>(x.size());
  a.jump_sigma_m = std::sqrt(sum2 / count);
  return a;
}

// Over `runs` simulations, each through `hold`: the median of the standard deviation (what compare
// and the windows score: of a drift-dominated log's runs the mean sd is well above the median, and a
// fit to the mean left the Telit HE910's 8x run's median window 15-41% below the log's sd; issue 27)
// and the mean of every other statistic. (Fitting the median of every statistic was tried before: the
// median of the differences and the autocorrelation is noisier over a few seeds, and on the Telit the
// compromise left the median over other seeds 34% low in east sd.)
std::array<AxisStats, 3> fit_stats(const noise::NoiseConfig& c, const EnuSeries& s, std::size_t window,
                                   std::uint64_t seed, int runs, const StaticHoldOptions& hold) {
  std::array<std::vector<AxisStats>, 3> per_run;
  auto out = simulated_stats(c, s, window, seed, runs, nullptr, &per_run, hold);
  for (std::size_t a = 0; a < 3; ++a) out[a].sd_m = quantile_stats(per_run[a], 0.5).sd_m;
  return out;
}

double log_error(double model, double real) {
  return real > 0.0 && model > 0.0 ? std::abs(std::log(model / real)) : (real == model ? 0.0 : 1.0);
}

}  // namespace

namespace {

// The composite's start shared by both smooth parts: jumps found in the first differences,
// jitter a quarter of the white share of the second differences; an axis with no spread is off.
noise::NoiseConfig composite_start(const EnuSeries& s, const std::array<AxisStats, 3>& real) {
  noise::NoiseConfig c;
  c.model = noise::Model::composite;
  auto& p = c.composite;
  // One quantum of the log's resolution (metres): 10^-decimals minutes of arc.
  const double q_north_m = 1852.0 * std::pow(10.0, -s.minute_decimals);
  const std::array<double, 3> quantum{q_north_m * std::cos(s.centre.lat_deg * std::numbers::pi / 180.0), q_north_m, 0.1};
  for (std::size_t a = 0; a < 3; ++a) {
    p.smooth_gm[a] = {0.0, 1.0};
    if (!(real[a].sd_m > 0.0)) continue;  // a constant axis: no noise
    p.axes[a] = find_jumps(s.axis_m[a], s.rate_hz, quantum[a]);
    p.axes[a].jitter_sigma_m = 0.25 * real[a].d2_sd_m / std::sqrt(6.0);
  }
  return c;
}

// The refit stops once the simulated sd, first- and second-difference sd are all this close (|ln ratio|).
constexpr double kRefitClose = 0.015;

double ratio_clamped(double want, double got) { return got > 0.0 ? std::clamp(want / got, 0.5, 2.0) : 2.0; }

// Simulated runs of each step of a refit: about 400 000 samples in all (8 to 32 runs of the log's
// length), and no more than `max_runs` (calibrate's --runs) when that is 8 or more; a quick
// calibration (fewer than 8) takes max(--runs, 2): a cgrw walk's burn-in (up to 100 000 steps a
// run) and its fit at every step made the refits most of calibrate's time on a short log.
int refit_runs(std::size_t samples, int max_runs) {
  if (quick_calibration(max_runs)) return std::max(max_runs, 2);
  const std::size_t most = static_cast<std::size_t>(std::clamp(max_runs, kMinRefitRuns, kMaxRefitRuns));
  return static_cast<int>(std::clamp<std::size_t>(400000 / std::max<std::size_t>(samples, 1), kMinRefitRuns, most));
}

int refit_iterations(int max_runs) { return quick_calibration(max_runs) ? kQuickRefitIterations : kRefitIterations; }

// Refits the smooth part and the jitter together against the rounded simulation (enough runs
// that a short log's sample spread, which varies much from run to run when tau is near the
// log's length, is not fitted to the luck of a few seeds): `adjust(axis, simulated)` moves the
// smooth part of one axis, the jitter follows the second differences. Returns the iteration
// nearest the log's standard deviation, first- and second-difference standard deviations (or,
// `whole_score`, with the lowest calibration::score: the walk's other statistics, its time scale,
// do not follow from those three as a gauss-markov's do).
template <class Adjust>
noise::NoiseConfig refit_composite(noise::NoiseConfig c, const EnuSeries& s, const std::array<AxisStats, 3>& real,
                                   std::size_t window, int iterations, bool whole_score, int max_runs, Adjust adjust,
                                   const StaticHoldOptions& hold = {}) {
  const int runs = refit_runs(s.size(), max_runs);
  noise::NoiseConfig best = c;
  double best_error = std::numeric_limits<double>::infinity();
  for (int iteration = 0; iteration < iterations; ++iteration) {
    const auto sim = fit_stats(c, s, window, 0x636f6d70ULL, runs, hold);
    double error = 0.0, worst = 0.0;
    for (std::size_t a = 0; a < 3; ++a)
      for (const double e : {log_error(sim[a].sd_m, real[a].sd_m), log_error(sim[a].d1_sd_m, real[a].d1_sd_m),
                             log_error(sim[a].d2_sd_m, real[a].d2_sd_m)})
        error += e, worst = std::max(worst, e);
    if (whole_score) error = score(real, sim);
    if (error < best_error) best_error = error, best = c;
    // Close enough: the runs' own spread is wider than that (and each iteration costs `runs` simulations).
    if (!whole_score && worst < kRefitClose) break;
    for (std::size_t a = 0; a < 3; ++a) {
      if (!(real[a].sd_m > 0.0)) continue;
      auto& jitter = c.composite.axes[a].jitter_sigma_m;
      jitter = std::clamp(jitter * ratio_clamped(real[a].d2_sd_m, sim[a].d2_sd_m), 1e-4 * real[a].d2_sd_m,
                          real[a].d2_sd_m);
      adjust(a, sim[a], c);
    }
  }
  return best;
}

}  // namespace

namespace {

// Fraction of a second-order Gauss-Markov process's variance lost to the mean of n samples:
// (1 + 2 sum_{k<n} (1 - k/n) rho(k dt)) / n.
double mean_share(double tau_s, std::size_t n, double dt) {
  double acc = 1.0;
  for (std::size_t k = 1; k < n; ++k) {
    const double r = noise::gauss_markov_autocorrelation(2, static_cast<double>(k) * dt, tau_s);
    if (r < 1e-12) break;
    acc += 2.0 * (1.0 - static_cast<double>(k) / static_cast<double>(n)) * r;
  }
  return std::min(acc / static_cast<double>(n), 1.0 - 1e-9);
}

struct SlowChoice {
  double share = 0.0, tau_s = 0.0, sigma_m = 0.0;
  bool tau_at_bound = false, sigma_at_bound = false;
};

// The sample autocorrelation at `lag_s` of a second-order Gauss-Markov process of time constant
// `tau_s` over n samples: (rho(L) - m) / (1 - m), m the share of its variance lost to the mean.
double sample_acf_gm2(double lag_s, double tau_s, std::size_t n, double dt) {
  const double m = mean_share(tau_s, n, dt);
  return (noise::gauss_markov_autocorrelation(2, lag_s, tau_s) - m) / (1.0 - m);
}

// Slow parts of one axis, best first (at most `count`): the share w of the log's sample variance
// (0.1 .. 0.8) and the time constant tau (5 s .. 4x the log's length) whose predicted sample
// autocorrelation at 10 and 30 s, (1 - w) rho_fast(L) + w (rho_slow(L) - m) / (1 - m) with m the
// share lost to the mean, is nearer the log's than the fast part's alone; none when none is.
// rho_fast is the simulated fast part's, corrected for the refit that follows: a gauss-markov-2
// smooth part (time constant `smooth_tau_s`, 0 = not one) left (1 - w) of the variance with the
// same first differences gets a time constant sqrt(1 - w) as long, and so less correlation (the
// prediction without that correction chose slow parts the refit then undid: issue 27).
std::vector<SlowChoice> choose_slow(const AxisStats& real, const AxisStats& fast, std::size_t n, double rate_hz,
                                    std::size_t count, double smooth_tau_s) {
  std::vector<std::pair<double, SlowChoice>> ranked;
  if (!real.acf_s[0] || !real.acf_s[1] || !fast.acf_s[0] || !fast.acf_s[1] || !(real.sd_m > 0.0)) return {};
  const double dt = 1.0 / rate_hz, length_s = static_cast<double>(n) * dt;
  const double max_tau = kCompositeMaxTauInLogs * length_s;
  const auto error = [&](double w, double tau, double m) {
    double e = 0.0;
    for (std::size_t i = 0; i < 2; ++i) {
      double slow = 0.0, fast_acf = *fast.acf_s[i];
      if (w > 0.0) slow = (noise::gauss_markov_autocorrelation(2, kAcfTimes_s[i], tau) - m) / (1.0 - m);
      if (w > 0.0 && smooth_tau_s > 0.0)
        fast_acf += sample_acf_gm2(kAcfTimes_s[i], smooth_tau_s * std::sqrt(1.0 - w), n, dt) -
                    sample_acf_gm2(kAcfTimes_s[i], smooth_tau_s, n, dt);
      const double predicted = (1.0 - w) * fast_acf + w * slow;
      e += (predicted - *real.acf_s[i]) * (predicted - *real.acf_s[i]);
    }
    return e;
  };
  const double none = error(0.0, 1.0, 0.0);
  if (none < 0.03 * 0.03) return {};  // within 0.03 at both lags already
  for (int ti = 0; ti <= 12; ++ti) {
    const double tau = std::exp(std::log(5.0) + (std::log(std::max(max_tau, 5.0)) - std::log(5.0)) * ti / 12.0);
    const double m = mean_share(tau, n, dt);
    for (int wi = 2; wi <= 16; wi += 2) {
      const double w = 0.05 * wi;
      const double e = error(w, tau, m);
      if (e >= none) continue;
      SlowChoice c;
      c.share = w, c.tau_s = tau;
      c.sigma_m = real.sd_m * std::sqrt(w / (1.0 - m));
      c.sigma_at_bound = c.sigma_m > kCompositeMaxSigmaInSd * real.sd_m;
      c.sigma_m = std::min(c.sigma_m, kCompositeMaxSigmaInSd * real.sd_m);
      c.tau_at_bound = tau >= 0.999 * max_tau;
      ranked.emplace_back(e, c);
    }
  }
  std::sort(ranked.begin(), ranked.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<SlowChoice> out;
  for (const auto& ranked_choice : ranked) {
    const SlowChoice& c = ranked_choice.second;
    // Distinct candidates: another share or a time constant at least 1.5x away.
    const bool near = std::any_of(out.begin(), out.end(), [&](const SlowChoice& o) {
      return std::abs(o.share - c.share) < 0.15 && std::abs(std::log(o.tau_s / c.tau_s)) < std::log(1.5);
    });
    if (!near) out.push_back(c);
    if (out.size() == count) break;
  }
  // And the best one no slower than the log's length when none of those is: a window of the log's
  // length holds a few of its time constants, so its sd is less skewed and the median window is
  // nearer the mean (a slow part at 4x the log's length gives the Telit HE910 windows of 0.3..3.2 m
  // whose median is 35-40% below the log's sd though their mean is not; issue 27).
  const auto short_tau = [&](const SlowChoice& c) { return c.tau_s <= length_s; };
  if (!out.empty() && std::none_of(out.begin(), out.end(), short_tau)) {
    const auto it = std::find_if(ranked.begin(), ranked.end(), [&](const auto& r) { return short_tau(r.second); });
    if (it != ranked.end()) out.push_back(it->second);
  }
  return out;
}

// Adds a slow part to a fitted composite `c` and refits the rest with `refit(c, fast_share)`
// (fast_share: the share of each axis's sample variance left to the smooth part), for the three
// best candidates by the predicted autocorrelation (the best one in a quick calibration) and the
// best no slower than the log's length; keeps whichever scores best on the median over the
// simulated runs, `c` itself included. Notes what was fitted and what hit a bound.
template <class Refit>
noise::NoiseConfig with_slow_part(const noise::NoiseConfig& c, const EnuSeries& s, const std::array<AxisStats, 3>& real,
                                  std::size_t window, std::vector<std::string>* notes, int max_runs, Refit refit,
                                  const StaticHoldOptions& hold = {}) {
  const std::size_t best_candidates = quick_calibration(max_runs) ? 1 : 3;
  const int runs = refit_runs(s.size(), max_runs);
  // Each candidate is scored on the median over the runs, as compare and the windows score it (the
  // mean over runs of a drift-dominated log's sd is well above its median; issue 27).
  const auto median_score = [&](const noise::NoiseConfig& k, std::array<AxisStats, 3>* mean) {
    std::array<std::vector<AxisStats>, 3> per_run;
    const auto m = simulated_stats(k, s, window, 0x736c6f77ULL, runs, nullptr, &per_run, hold);
    if (mean) *mean = m;
    const std::array<AxisStats, 3> med{quantile_stats(per_run[0], 0.5), quantile_stats(per_run[1], 0.5),
                                       quantile_stats(per_run[2], 0.5)};
    return score(real, med);
  };
  std::array<AxisStats, 3> fast{};
  const double without = median_score(c, &fast);
  std::array<std::vector<SlowChoice>, 2> choices;
  for (std::size_t a = 0; a < 2; ++a)  // horizontal axes: the vertical keeps its fit
    choices[a] = choose_slow(real[a], fast[a], s.size(), s.rate_hz, best_candidates,
                             c.composite.smooth == noise::CompositeSmooth::gauss_markov_2 ? c.composite.smooth_gm[a].tau_s
                                                                                         : 0.0);
  noise::NoiseConfig best = c;
  double best_score = without;
  std::string best_parts;
  const std::size_t candidates = std::max(choices[0].size(), choices[1].size());
  for (std::size_t k = 0; k < candidates; ++k) {
    noise::NoiseConfig slow = c;
    std::array<double, 3> fast_share{1.0, 1.0, 1.0};
    std::string parts;
    for (std::size_t a = 0; a < 2; ++a) {
      if (choices[a].empty()) continue;
      const SlowChoice& x = choices[a][std::min(k, choices[a].size() - 1)];
      slow.composite.axes[a].slow_sigma_m = x.sigma_m;
      slow.composite.axes[a].slow_tau_s = x.tau_s;
      fast_share[a] = 1.0 - x.share;
      parts += fmt::format("; {} {:.0f}% of the variance, tau {:.3g} s{}{}", kAxisNames[a], 100 * x.share, x.tau_s,
                           x.tau_at_bound ? " (at its bound, 4x the log's length)" : "",
                           x.sigma_at_bound ? " (sigma at its bound, 5x the log's sd)" : "");
    }
    if (parts.empty()) break;
    slow = refit(slow, fast_share);
    const double with = median_score(slow, nullptr);
    if (with < best_score) best_score = with, best = slow, best_parts = parts;
  }
  if (notes && (!choices[0].empty() || !choices[1].empty())) {
    const char* smooth = c.composite.smooth == noise::CompositeSmooth::cgrw ? "cgrw" : "gauss-markov-2";
    notes->push_back(best_parts.empty()
                         ? fmt::format("composite ({} smooth part): no slow part scored better than none ({:.3f})",
                                       smooth, without)
                         : fmt::format("composite ({} smooth part): slow part fitted on the autocorrelation at 10 and "
                                       "30 s{}: score {:.3f} with it, {:.3f} without", smooth, best_parts, best_score,
                                       without));
  }
  return best;
}

// Notes a smooth gauss-markov-2 part whose tau or sigma hit the composite's bounds.
void note_smooth_bounds(const noise::NoiseConfig& c, const EnuSeries& s, const std::array<AxisStats, 3>& real,
                        std::vector<std::string>* notes) {
  if (!notes || c.composite.smooth != noise::CompositeSmooth::gauss_markov_2) return;
  const double length_s = s.duration_s();
  for (std::size_t a = 0; a < 3; ++a) {
    const auto& g = c.composite.smooth_gm[a];
    if (!(real[a].sd_m > 0.0)) continue;
    if (g.tau_s >= 0.999 * kCompositeMaxTauInLogs * length_s || g.sigma_m >= 0.999 * kCompositeMaxSigmaInSd * real[a].sd_m)
      notes->push_back(fmt::format("composite {}: smooth part at its bound (tau {:.3g} s of at most {:.3g} s, 4x the log's "
                                   "length; sigma {:.3g} m of at most {:.3g} m, 5x the log's sd): the log is "
                                   "drift-dominated, and runs longer than it stay within that spread",
                                   kAxisNames[a], g.tau_s, kCompositeMaxTauInLogs * length_s, g.sigma_m,
                                   kCompositeMaxSigmaInSd * real[a].sd_m));
  }
}

}  // namespace

noise::NoiseConfig fit_composite(const EnuSeries& s, const std::array<AxisStats, 3>& real, std::size_t window,
                                 std::vector<std::string>* notes, const StaticHoldOptions& hold, int max_runs) {
  noise::NoiseConfig c = composite_start(s, real);
  std::array<double, 3> sd_target{}, d1_target{};
  const double max_tau_s = kCompositeMaxTauInLogs * s.duration_s();
  constexpr double kMinKeptBounded = 1.0 / (kCompositeMaxSigmaInSd * kCompositeMaxSigmaInSd);
  const auto smooth = [&](std::size_t a, noise::NoiseConfig& k) {
    k.composite.smooth_gm[a] =
        fit_gauss_markov(sd_target[a], d1_target[a], s.size(), s.rate_hz, 2, max_tau_s, kMinKeptBounded);
    k.composite.smooth_gm[a].sigma_m = std::min(k.composite.smooth_gm[a].sigma_m, kCompositeMaxSigmaInSd * real[a].sd_m);
    if (k.composite.axes[a].jump_rate_hz > 0.0) k.composite.axes[a].jump_decay_s = k.composite.smooth_gm[a].tau_s;
  };
  std::array<double, 3> share{1.0, 1.0, 1.0};
  const auto adjust = [&](std::size_t a, const AxisStats& sim, noise::NoiseConfig& k) {
    const double sd_real = std::sqrt(share[a]) * real[a].sd_m;
    sd_target[a] = std::clamp(sd_target[a] * ratio_clamped(real[a].sd_m, sim.sd_m), 0.2 * sd_real, 3.0 * sd_real);
    d1_target[a] = std::clamp(d1_target[a] * ratio_clamped(real[a].d1_sd_m, sim.d1_sd_m), 0.02 * real[a].d1_sd_m,
                              3.0 * real[a].d1_sd_m);
    smooth(a, k);
  };
  for (std::size_t a = 0; a < 3; ++a)
    if (real[a].sd_m > 0.0) sd_target[a] = real[a].sd_m, d1_target[a] = real[a].d1_sd_m, smooth(a, c);
  c = refit_composite(c, s, real, window, refit_iterations(max_runs), false, max_runs, adjust, hold);
  const std::array<double, 3> sd_fast = sd_target, d1_fast = d1_target;
  noise::NoiseConfig out = with_slow_part(c, s, real, window, notes, max_runs, [&](noise::NoiseConfig k, const std::array<double, 3>& fast) {
    share = fast;
    for (std::size_t a = 0; a < 3; ++a)
      if (real[a].sd_m > 0.0) sd_target[a] = std::sqrt(fast[a]) * sd_fast[a], d1_target[a] = d1_fast[a], smooth(a, k);
    return refit_composite(k, s, real, window, refit_iterations(max_runs), false, max_runs, adjust, hold);
  }, hold);
  note_smooth_bounds(out, s, real, notes);
  return out;
}

noise::NoiseConfig fit_composite_cgrw(const EnuSeries& s, const std::array<AxisStats, 3>& real, std::size_t window,
                                      std::vector<std::string>* notes, int max_runs) {
  noise::NoiseConfig c = composite_start(s, real);
  c.composite.smooth = noise::CompositeSmooth::cgrw;
  c.cgrw.rate_hz = s.rate_hz;
  c.cgrw.window_s = static_cast<double>(window) / s.rate_hz;
  const double w = static_cast<double>(window);
  const std::array<noise::CgrwAxis noise::CgrwParams::*, 3> axes{&noise::CgrwParams::east, &noise::CgrwParams::north,
                                                                 &noise::CgrwParams::up};
  std::array<noise::CgrwAxis, 3> target{};
  const auto smooth = [&](std::size_t a, noise::NoiseConfig& k) {
    target[a] = noise::nudge_cgrw_axis(target[a]);
    noise::CgrwFit fit;
    k.cgrw.*axes[a] = written_cgrw(target[a], w, a, fit);
  };
  for (std::size_t a = 0; a < 3; ++a) {
    if (!(real[a].sd_m > 0.0)) continue;
    // Jumps decay with the smooth wander's time scale (the gauss-markov-2 tau of the log).
    if (c.composite.axes[a].jump_rate_hz > 0.0)
      c.composite.axes[a].jump_decay_s = fit_gauss_markov(real[a].sd_m, real[a].d1_sd_m, s.size(), s.rate_hz, 2).tau_s;
    target[a] = real[a].cgrw;
    smooth(a, c);
  }
  // The walk is scale-invariant: all four statistics scale the spread, the three of the
  // differences the first differences, the two of the second differences the second differences.
  const auto adjust = [&](std::size_t a, const AxisStats& sim, noise::NoiseConfig& k) {
    const double k_sd = ratio_clamped(real[a].sd_m, sim.sd_m);
    const double k_d1 = ratio_clamped(real[a].d1_sd_m, sim.d1_sd_m) / k_sd;
    const double k_d2 = ratio_clamped(real[a].d2_sd_m, sim.d2_sd_m) / (k_sd * k_d1);
    target[a] = {target[a].width_m * k_sd, target[a].width_d1_m * k_sd * k_d1,
                 target[a].width_d2_m * k_sd * k_d1 * k_d2, target[a].sigma_d2_m * k_sd * k_d1 * k_d2};
    smooth(a, k);
  };
  c = refit_composite(c, s, real, window, refit_iterations(max_runs), true, max_runs, adjust);
  const auto fitted = target;
  return with_slow_part(c, s, real, window, notes, max_runs, [&](noise::NoiseConfig k, const std::array<double, 3>& fast) {
    for (std::size_t a = 0; a < 3; ++a) {
      if (!(real[a].sd_m > 0.0)) continue;
      const double f = std::sqrt(fast[a]);  // the walk's spread shrinks to the fast share
      target[a] = {fitted[a].width_m * f, fitted[a].width_d1_m, fitted[a].width_d2_m, fitted[a].sigma_d2_m};
      smooth(a, k);
    }
    return refit_composite(k, s, real, window, refit_iterations(max_runs), true, max_runs, adjust);
  });
}

}  // namespace gpsemu::calibration
