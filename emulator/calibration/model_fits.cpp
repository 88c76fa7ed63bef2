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

// Downhill simplex (Nelder & Mead 1965) on a deterministic objective; returns the best vertex.
template <class F>
std::array<double, 3> nelder_mead(F f, std::array<double, 3> x0, double step, int evaluations) {
  using P = std::array<double, 3>;
  std::array<P, 4> v{x0, x0, x0, x0};
  for (int i = 0; i < 3; ++i) v[i + 1][i] += step;
  std::array<double, 4> fv{};
  for (int i = 0; i < 4; ++i) fv[i] = f(v[i]);
  int used = 4;
  const auto along = [](const P& c, const P& w, double t) {
    P r{};
    for (int i = 0; i < 3; ++i) r[i] = c[i] + t * (w[i] - c[i]);
    return r;
  };
  while (used < evaluations) {
    std::array<int, 4> order{0, 1, 2, 3};
    std::sort(order.begin(), order.end(), [&](int a, int b) { return fv[a] < fv[b]; });
    std::array<P, 4> sv;
    std::array<double, 4> sf{};
    for (int i = 0; i < 4; ++i) sv[i] = v[order[i]], sf[i] = fv[order[i]];
    v = sv, fv = sf;
    if (fv[3] - fv[0] < 1e-4) break;
    P c{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) c[j] += v[i][j] / 3.0;
    const P xr = along(c, v[3], -1.0);
    const double fr = f(xr);
    ++used;
    if (fr < fv[0]) {
      const P xe = along(c, v[3], -2.0);
      const double fe = f(xe);
      ++used;
      if (fe < fr) v[3] = xe, fv[3] = fe;
      else v[3] = xr, fv[3] = fr;
    } else if (fr < fv[2]) {
      v[3] = xr, fv[3] = fr;
    } else {
      const P xc = along(c, v[3], fr < fv[3] ? -0.5 : 0.5);
      const double fc = f(xc);
      ++used;
      if (fc < std::min(fr, fv[3])) {
        v[3] = xc, fv[3] = fc;
      } else {  // shrink towards the best
        for (int i = 1; i < 4; ++i) {
          v[i] = along(v[0], v[i], 0.5);
          fv[i] = f(v[i]);
          ++used;
        }
      }
    }
  }
  const auto best = std::min_element(fv.begin(), fv.end()) - fv.begin();
  return v[static_cast<std::size_t>(best)];
}

}  // namespace

noise::GaussMarkovAxis fit_gauss_markov(std::span<const double> x, double rate_hz, int order) {
  const AxisStats s = measure_axis(x, rate_hz, x.size());
  return fit_gauss_markov(s.sd_m, s.d1_sd_m, x.size(), rate_hz, order);
}

noise::GaussMarkovAxis fit_gauss_markov(double sd_m, double d1_sd_m, std::size_t n, double rate_hz,
                                        int order, double max_tau_s, double min_kept) {
  struct {
    double sd_m, d1_sd_m;
  } s{sd_m, d1_sd_m};
  const double dt = 1.0 / rate_hz;
  // Fraction of sigma^2 a series of n samples keeps about its own mean: 1 - var(mean) / sigma^2.
  const auto kept = [&](double tau) {
    double acc = 1.0;
    for (std::size_t k = 1; k < n; ++k) {
      const double r = noise::gauss_markov_autocorrelation(order, static_cast<double>(k) * dt, tau);
      if (r < 1e-12) break;
      acc += 2.0 * (1.0 - static_cast<double>(k) / static_cast<double>(n)) * r;
    }
    return std::max(1.0 - acc / static_cast<double>(n), 1e-12);
  };
  const auto ratio = [&](double tau) {  // E[d1^2] / (2 E[sample variance])
    return (1.0 - noise::gauss_markov_autocorrelation(order, dt, tau)) / kept(tau);
  };
  const double want = s.sd_m > 0.0 ? s.d1_sd_m * s.d1_sd_m / (2.0 * s.sd_m * s.sd_m) : 1.0;
  double lo = std::log(0.05 * dt), hi = std::log(max_tau_s > 0.0 ? std::max(max_tau_s, 0.1 * dt)
                                                                   : 10.0 * static_cast<double>(n) * dt);
  double tau = 0.0;
  if (want >= ratio(std::exp(lo))) {
    tau = std::exp(lo);
  } else if (want <= ratio(std::exp(hi))) {
    tau = std::exp(hi);
  } else {
    for (int i = 0; i < 60; ++i) {  // the ratio falls as tau grows
      const double mid = 0.5 * (lo + hi);
      (ratio(std::exp(mid)) > want ? lo : hi) = mid;
    }
    tau = std::exp(0.5 * (lo + hi));
  }
  return {s.sd_m / std::sqrt(std::max(kept(tau), min_kept)), tau};
}

noise::ChronoParams fit_chrono(const EnuSeries& series, const std::array<AxisStats, 3>& real) {
  const double rate = series.rate_hz;
  // Start from the oscillator the walk is: omega^2 = 0.2 sigma, velocity amplitude about
  // omega x position amplitude; clamps at twice the typical velocity and acceleration.
  double sd = 0.0, d1 = 0.0, d2 = 0.0;
  for (const AxisStats& a : real) sd += a.sd_m / 3, d1 += a.d1_sd_m / 3, d2 += a.d2_sd_m / 3;
  const double omega = std::max(d1 * rate / std::max(sd, 1e-6), 1e-4);
  const std::array<double, 3> x0{std::log(std::max(omega * omega / 0.2, 1e-8)),
                                 std::log(std::max(2.0 * d1 * rate, 1e-5)),
                                 std::log(std::max(2.0 * d2 * rate * rate, 1e-6))};
  const std::size_t window = series.size();
  const auto params = [&](const std::array<double, 3>& x) {
    noise::ChronoParams p;
    p.mean = 0.0;
    p.sigma = std::exp(x[0]);
    p.update_rate_hz = rate;
    p.v_max_mps = std::exp(x[1]);
    p.a_max_mps2 = std::exp(x[2]);
    return p;
  };
  const auto objective = [&](const std::array<double, 3>& x) {
    noise::NoiseConfig c;
    c.model = noise::Model::chrono;
    c.chrono = params(x);
    return score(real, simulated_stats(c, series, window, 0x63687266ULL, 2, nullptr));
  };
  const int budget = series.size() > 20000 ? 60 : 150;
  return params(nelder_mead(objective, x0, 1.0, budget));
}


std::array<noise::GaussMarkovAxis, 3> fit_gauss_markov_dequantised(const EnuSeries& s,
                                                                   const std::array<AxisStats, 3>& real,
                                                                   std::size_t window, int order) {
  noise::NoiseConfig gm;
  gm.model = noise::Model::gauss_markov;
  gm.gauss_markov_order = order;
  std::array<double, 3> sd_target{}, d1_target{};
  for (std::size_t a = 0; a < 3; ++a) {
    gm.gauss_markov[a] = fit_gauss_markov(s.axis_m[a], s.rate_hz, order);
    sd_target[a] = real[a].sd_m, d1_target[a] = real[a].d1_sd_m;
  }
  for (int iteration = 0; iteration < 4; ++iteration) {
    const auto sim = simulated_stats(gm, s, window, 0x676d666974ULL, 16, nullptr);
    for (std::size_t a = 0; a < 3; ++a) {
      // Bounded corrections: where the process cannot reach the log (order 1 on a smooth
      // receiver) they would otherwise grow without end.
      if (sim[a].sd_m > 0.0)
        sd_target[a] = std::clamp(sd_target[a] * real[a].sd_m / sim[a].sd_m, 0.5 * real[a].sd_m, 2.0 * real[a].sd_m);
      if (sim[a].d1_sd_m > 0.0)
        d1_target[a] = std::clamp(d1_target[a] * real[a].d1_sd_m / sim[a].d1_sd_m, 0.25 * real[a].d1_sd_m,
                                  2.0 * real[a].d1_sd_m);
      gm.gauss_markov[a] = fit_gauss_markov(sd_target[a], d1_target[a], s.size(), s.rate_hz, order);
    }
  }
  return gm.gauss_markov;
}

namespace {

// The statistics written for one axis from `target`: as they are when the walk reaches them
// within the emulator's accepted factor, else the fit's best compromise, nudged; checked the way
// the emulator will check them (the compromise refitted may land elsewhere: its own compromise
// is taken then, and after three tries the preset's shape at the target's width, which the walk
// always reaches).
// As the config file prints it (6 significant digits) and the emulator reads it back.
noise::CgrwAxis as_printed(const noise::CgrwAxis& x) {
  const auto r = [](double v) { return std::stod(fmt::format("{:.6g}", v)); };
  return noise::nudge_cgrw_axis({r(x.width_m), r(x.width_d1_m), r(x.width_d2_m), r(x.sigma_d2_m)});
}

}  // namespace

noise::CgrwAxis written_cgrw(const noise::CgrwAxis& target, double window, std::size_t a, noise::CgrwFit& fit) {
  const std::string name = fmt::format("cgrw.{}", kAxisNames[a]);
  constexpr double kAny = std::numeric_limits<double>::infinity();
  fit = noise::fit_cgrw_axis(target, window, name, kAny);
  noise::CgrwAxis w = as_printed(fit.worst_ratio <= noise::kCgrwMaxFitRatio ? target : fit.achieved);
  for (int attempt = 0; attempt < 3; ++attempt) {
    const noise::CgrwFit check = noise::fit_cgrw_axis(w, window, name, kAny);
    if (check.worst_ratio <= 0.95 * noise::kCgrwMaxFitRatio) return w;
    w = as_printed(check.achieved);
  }
  const noise::CgrwParams preset = noise::cgrw_preset(w.width_m);
  fit = noise::fit_cgrw_axis(preset.east, window, name, kAny);
  return preset.east;
}

noise::CgrwParams fit_cgrw_dequantised(const EnuSeries& s, const std::array<AxisStats, 3>& real,
                                       std::size_t window, std::array<noise::CgrwFit, 3>& fits,
                                       std::vector<std::string>& notes) {
  noise::NoiseConfig cgrw;
  cgrw.model = noise::Model::cgrw;
  cgrw.cgrw.rate_hz = s.rate_hz;
  cgrw.cgrw.window_s = static_cast<double>(window) / s.rate_hz;
  const double w = static_cast<double>(window);
  std::array<noise::CgrwAxis*, 3> axes{&cgrw.cgrw.east, &cgrw.cgrw.north, &cgrw.cgrw.up};
  std::array<noise::CgrwAxis, 3> target{};
  for (std::size_t a = 0; a < 3; ++a) {
    bool nudged = false;
    target[a] = noise::nudge_cgrw_axis(real[a].cgrw, &nudged);
    if (nudged && !noise::cgrw_axis_off(target[a])) {
      const auto& m = real[a].cgrw;
      notes.push_back(fmt::format("cgrw {}: measured {:.6g},{:.6g},{:.6g},{:.6g} is outside the walk's valid "
                                  "region (W1 <= 2 W, W2 <= 2 W1, S2 <= W2 / 2); nudged to {:.6g},{:.6g},{:.6g},{:.6g}",
                                  kAxisNames[a], m.width_m, m.width_d1_m, m.width_d2_m, m.sigma_d2_m,
                                  target[a].width_m, target[a].width_d1_m, target[a].width_d2_m, target[a].sigma_d2_m));
    }
    *axes[a] = written_cgrw(target[a], w, a, fits[a]);
  }
  // De-quantise: correct the targets by real / simulated (the simulation is rounded to the log's
  // resolution as the emulator's output is) and keep the correction when it scores better.
  const std::uint64_t seed = 0x6367727771ULL;
  double best_score = score(real, simulated_stats(cgrw, s, window, seed, 4, nullptr));
  noise::NoiseConfig trial = cgrw;
  std::array<noise::CgrwFit, 3> trial_fits = fits;
  for (int iteration = 0; iteration < 2; ++iteration) {
    const auto sim = simulated_stats(trial, s, window, seed, 4, nullptr);
    std::array<noise::CgrwAxis*, 3> t{&trial.cgrw.east, &trial.cgrw.north, &trial.cgrw.up};
    for (std::size_t a = 0; a < 3; ++a) {
      if (noise::cgrw_axis_off(target[a])) continue;
      const auto ratio = [](double want, double got) { return got > 0.0 ? std::clamp(want / got, 0.5, 2.0) : 1.0; };
      target[a].width_m *= ratio(real[a].cgrw.width_m, sim[a].cgrw.width_m);
      target[a].width_d1_m *= ratio(real[a].cgrw.width_d1_m, sim[a].cgrw.width_d1_m);
      target[a].width_d2_m *= ratio(real[a].cgrw.width_d2_m, sim[a].cgrw.width_d2_m);
      target[a].sigma_d2_m *= ratio(real[a].cgrw.sigma_d2_m, sim[a].cgrw.sigma_d2_m);
      target[a] = noise::nudge_cgrw_axis(target[a]);
      *t[a] = written_cgrw(target[a], w, a, trial_fits[a]);
    }
    const double sc = score(real, simulated_stats(trial, s, window, seed, 4, nullptr));
    if (sc < best_score) {
      best_score = sc, cgrw = trial, fits = trial_fits;
      notes.push_back(fmt::format("cgrw: statistics de-quantised (corrected for the {}-decimal rounding the "
                                  "emulator applies again), pass {}", s.minute_decimals, iteration + 1));
    }
  }
  return cgrw.cgrw;
}

}  // namespace gpsemu::calibration
