#include "emulator/calibration/calibrate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/model/geo.hpp"
#include "emulator/model/noise/cgrw_model.hpp"
#include "emulator/model/noise/gauss_markov_model.hpp"
#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::calibration {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const char* const kAxisNames[3] = {"east", "north", "up"};
// Least fraction of a Gauss-Markov process's variance a log is taken to show about its mean:
// sigma is at most 5x the log's standard deviation (a log much shorter than tau says little
// about sigma).
constexpr double kMinKept = 1.0 / 25.0;

std::array<AxisStats, 3> measure_all(const std::array<std::vector<double>, 3>& x, double rate_hz,
                                     std::size_t window) {
  return {measure_axis(x[0], rate_hz, window), measure_axis(x[1], rate_hz, window),
          measure_axis(x[2], rate_hz, window)};
}

std::array<AxisStats, 3> mean_over_runs(const noise::NoiseConfig& config, const EnuSeries& series,
                                        std::size_t window, std::uint64_t seed, int runs,
                                        std::array<std::vector<double>, 3>* first_run) {
  std::array<std::vector<AxisStats>, 3> per_axis;
  for (int r = 0; r < runs; ++r) {
    auto x = simulate(config, series, seed + static_cast<std::uint64_t>(r));
    const auto s = measure_all(x, series.rate_hz, window);
    for (std::size_t a = 0; a < 3; ++a) per_axis[a].push_back(s[a]);
    if (r == 0 && first_run) *first_run = std::move(x);
  }
  return {mean_stats(per_axis[0]), mean_stats(per_axis[1]), mean_stats(per_axis[2])};
}

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

std::array<std::vector<double>, 3> simulate(const noise::NoiseConfig& config, const EnuSeries& series,
                                            std::uint64_t seed) {
  auto model = noise::make_noise_model(config, seed);
  const LocalFrame frame(series.centre);
  nmea::FormatOptions format;
  format.minute_decimals = std::clamp(series.minute_decimals, 1, 8);
  nmea::Fix fix;
  fix.quality = nmea::FixQuality::gps;
  fix.dimension = nmea::FixDimension::three_d;
  fix.satellites_used = 12;
  fix.hdop = 1.0;
  std::array<std::vector<double>, 3> out;
  for (auto& a : out) a.assign(series.size(), kNaN);
  for (std::size_t k = 0; k < series.size(); ++k) {
    const auto t = std::chrono::nanoseconds(std::llround(static_cast<double>(k) * 1e9 / series.rate_hz));
    const Enu e = model->offset_at(t);  // every epoch, so gaps do not change the process
    if (std::isnan(series.axis_m[0][k])) continue;
    const Geodetic g = frame.to_geodetic(e);
    fix.lat_deg = g.lat_deg;
    fix.lon_deg = wrap_lon_deg(g.lon_deg);
    fix.alt_msl_m = g.alt_m;
    const auto sentence = nmea::parse_sentence(nmea::format_gga(fix, format));
    const auto gga = sentence ? nmea::parse_gga(*sentence) : nmea::Result<nmea::GgaData>(nmea::ParseError::wrong_type);
    if (!gga || !gga->lat_deg || !gga->lon_deg || !gga->alt_msl_m)
      throw std::logic_error("calibration: the emulator's own GGA did not parse back");
    const Enu r = frame.to_enu({*gga->lat_deg, *gga->lon_deg, *gga->alt_msl_m});
    out[0][k] = r.east_m, out[1][k] = r.north_m, out[2][k] = r.up_m;
  }
  return out;
}

std::string model_label(const noise::NoiseConfig& config) {
  if (config.model == noise::Model::gauss_markov && config.gauss_markov_order == 2) return "gauss-markov-2";
  return noise::to_string(config.model);
}

noise::GaussMarkovAxis fit_gauss_markov(std::span<const double> x, double rate_hz, int order) {
  const AxisStats s = measure_axis(x, rate_hz, x.size());
  return fit_gauss_markov(s.sd_m, s.d1_sd_m, x.size(), rate_hz, order);
}

noise::GaussMarkovAxis fit_gauss_markov(double sd_m, double d1_sd_m, std::size_t n, double rate_hz,
                                        int order) {
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
  double lo = std::log(0.05 * dt), hi = std::log(10.0 * static_cast<double>(n) * dt);
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
  return {s.sd_m / std::sqrt(std::max(kept(tau), kMinKept)), tau};
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
    return score(real, mean_over_runs(c, series, window, 0x63687266ULL, 2, nullptr));
  };
  const int budget = series.size() > 20000 ? 60 : 150;
  return params(nelder_mead(objective, x0, 1.0, budget));
}

Calibration calibrate(ReceiverLog log, const CalibrateOptions& options) {
  if (options.runs < 1) throw std::invalid_argument("runs must be >= 1");
  Calibration c;
  c.series = to_enu_series(log);
  c.counts = log.counts;
  const EnuSeries& s = c.series;
  c.window_samples = std::min<std::size_t>(s.size(), static_cast<std::size_t>(noise::kCgrwMaxWindowSamples));
  c.real = measure_all(s.axis_m, s.rate_hz, c.window_samples);
  if (c.real[0].sd_m <= 0.0 && c.real[1].sd_m <= 0.0)
    throw std::invalid_argument("the log's horizontal position never changes: nothing to calibrate");

  // cgrw: the report's four statistics over the log's length at its rate.
  noise::NoiseConfig cgrw;
  cgrw.model = noise::Model::cgrw;
  cgrw.cgrw.rate_hz = s.rate_hz;
  cgrw.cgrw.window_s = static_cast<double>(c.window_samples) / s.rate_hz;
  std::array<noise::CgrwAxis*, 3> written{&cgrw.cgrw.east, &cgrw.cgrw.north, &cgrw.cgrw.up};
  try {
    for (std::size_t a = 0; a < 3; ++a) {
      c.cgrw_measured[a] = c.real[a].cgrw;
      c.cgrw_fit[a] = noise::fit_cgrw_axis(c.cgrw_measured[a], static_cast<double>(c.window_samples),
                                           fmt::format("cgrw.{}", kAxisNames[a]),
                                           std::numeric_limits<double>::infinity());
      *written[a] = c.cgrw_fit[a].worst_ratio <= noise::kCgrwMaxFitRatio ? c.cgrw_measured[a]
                                                                         : c.cgrw_fit[a].achieved;
    }
    (void)noise::make_noise_model(cgrw, 1);  // the emulator must accept what is written
  } catch (const std::exception& e) {
    c.cgrw_unusable = e.what();
  }

  noise::NoiseConfig chrono;
  chrono.model = noise::Model::chrono;
  chrono.chrono = fit_chrono(s, c.real);

  noise::NoiseConfig gaussian;
  gaussian.model = noise::Model::gaussian;
  noise::NoiseConfig gm1, gm2;
  gm1.model = gm2.model = noise::Model::gauss_markov;
  gm1.gauss_markov_order = 1;
  gm2.gauss_markov_order = 2;
  for (std::size_t a = 0; a < 3; ++a) {
    double mean = 0.0, n = 0.0;
    for (double v : s.axis_m[a])
      if (!std::isnan(v)) mean += v, n += 1;
    gaussian.gaussian[a] = {mean / n, c.real[a].sd_m};
    gm1.gauss_markov[a] = fit_gauss_markov(s.axis_m[a], s.rate_hz, 1);
    gm2.gauss_markov[a] = fit_gauss_markov(s.axis_m[a], s.rate_hz, 2);
  }

  // The log's output resolution makes first differences coarser than the process under it (a
  // 4-decimal log moves in 0.1-0.2 m quanta): refit the gauss-markov processes until their
  // rounded simulation has the log's standard deviation and first-difference standard deviation.
  for (noise::NoiseConfig* gm : {&gm1, &gm2}) {
    std::array<double, 3> sd_target{}, d1_target{};
    for (std::size_t a = 0; a < 3; ++a) sd_target[a] = c.real[a].sd_m, d1_target[a] = c.real[a].d1_sd_m;
    for (int iteration = 0; iteration < 4; ++iteration) {
      const auto sim = mean_over_runs(*gm, s, c.window_samples, 0x676d666974ULL, 16, nullptr);
      for (std::size_t a = 0; a < 3; ++a) {
        // Bounded corrections: where the process cannot reach the log (order 1 on a smooth
        // receiver) they would otherwise grow without end.
        if (sim[a].sd_m > 0.0)
          sd_target[a] = std::clamp(sd_target[a] * c.real[a].sd_m / sim[a].sd_m, 0.5 * c.real[a].sd_m,
                                    2.0 * c.real[a].sd_m);
        if (sim[a].d1_sd_m > 0.0)
          d1_target[a] = std::clamp(d1_target[a] * c.real[a].d1_sd_m / sim[a].d1_sd_m,
                                    0.25 * c.real[a].d1_sd_m, 2.0 * c.real[a].d1_sd_m);
        gm->gauss_markov[a] =
            fit_gauss_markov(sd_target[a], d1_target[a], s.size(), s.rate_hz, gm->gauss_markov_order);
      }
    }
  }

  std::vector<noise::NoiseConfig> configs;
  if (c.cgrw_unusable.empty()) configs.push_back(cgrw);
  configs.push_back(chrono);
  configs.push_back(gaussian);
  configs.push_back(gm1);
  configs.push_back(gm2);
  for (const noise::NoiseConfig& config : configs) {
    ModelResult r;
    r.config = config;
    r.stats = mean_over_runs(config, s, c.window_samples, options.seed, options.runs, &r.first_run_m);
    r.score = score(c.real, r.stats);
    c.models.push_back(std::move(r));
  }
  for (std::size_t i = 1; i < c.models.size(); ++i)
    if (c.models[i].score < c.models[c.best].score) c.best = i;
  return c;
}

std::string config_toml(const Calibration& c, const std::string& log_name) {
  const EnuSeries& s = c.series;
  const LogCounts& n = c.counts;
  std::string out;
  const auto line = [&out](const std::string& text) { out += text + "\n"; };
  line(fmt::format("# gpsemu calibrate {}", log_name));
  line(fmt::format("# {} fixes over {:.0f} s at {} Hz ({} missing epochs), {} decimals of minutes; "
                   "skipped: {} no-fix GGA, {} malformed GGA, {} repeated times, {} bad checksums, "
                   "{} malformed sentences, {} binary/garbage bytes",
                   s.size() - n.missing_epochs, s.duration_s(), s.rate_hz, n.missing_epochs,
                   s.minute_decimals, n.gga_no_fix, n.gga_malformed, n.repeated_time,
                   n.stream.bad_checksum, n.stream.malformed, n.stream.garbage_bytes));
  std::string scores;
  for (const ModelResult& m : c.models)
    scores += fmt::format(" {} {:.3f}", model_label(m.config), m.score);
  line(fmt::format("# score (mean |ln(model/real)| over the compared statistics, lower is better):{}",
                   scores));
  line(fmt::format("noise = \"{}\"", noise::to_string(c.models[c.best].config.model)));
  line(fmt::format("rate = {}", s.rate_hz));
  line(fmt::format("resolution = {}", std::clamp(s.minute_decimals, 1, 8)));
  line(fmt::format("origin = \"{:.9f},{:.9f},{:.2f}\"", s.centre.lat_deg, s.centre.lon_deg, s.centre.alt_m));
  const ModelResult* best_gm = nullptr;  // the gauss-markov order whose keys are written
  for (const ModelResult& m : c.models)
    if (m.config.model == noise::Model::gauss_markov && (!best_gm || m.score < best_gm->score)) best_gm = &m;
  for (const ModelResult& m : c.models) {
    const noise::NoiseConfig& k = m.config;
    switch (k.model) {
      case noise::Model::cgrw: {
        const std::array<const noise::CgrwAxis*, 3> axes{&k.cgrw.east, &k.cgrw.north, &k.cgrw.up};
        for (std::size_t a = 0; a < 3; ++a) {
          if (c.cgrw_fit[a].worst_ratio > noise::kCgrwMaxFitRatio) {
            const auto& w = c.cgrw_measured[a];
            line(fmt::format("# cgrw {}: measured {:.6g},{:.6g},{:.6g},{:.6g} is out of the walk's reach "
                             "(best fit off by x{:.2f}); its best compromise is written", kAxisNames[a],
                             w.width_m, w.width_d1_m, w.width_d2_m, w.sigma_d2_m, c.cgrw_fit[a].worst_ratio));
          }
          const auto* x = axes[a];
          line(fmt::format("cgrw-{} = \"{:.6g},{:.6g},{:.6g},{:.6g}\"", kAxisNames[a], x->width_m,
                           x->width_d1_m, x->width_d2_m, x->sigma_d2_m));
        }
        line(fmt::format("cgrw-rate = {}", k.cgrw.rate_hz));
        line(fmt::format("cgrw-window = {:.6g}", k.cgrw.window_s));
        break;
      }
      case noise::Model::chrono:
        line(fmt::format("chrono = \"{:.6g},{:.6g},{},{:.6g},{:.6g}\"", k.chrono.mean, k.chrono.sigma,
                         k.chrono.update_rate_hz, k.chrono.v_max_mps, k.chrono.a_max_mps2));
        break;
      case noise::Model::gaussian: {
        const auto& g = k.gaussian;
        line(fmt::format("gaussian-mean = \"{:.3g},{:.3g},{:.3g}\"", g[0].mean_m, g[1].mean_m, g[2].mean_m));
        line(fmt::format("gaussian-sigma = \"{:.6g},{:.6g},{:.6g}\"", g[0].sigma_m, g[1].sigma_m, g[2].sigma_m));
        break;
      }
      case noise::Model::gauss_markov: {
        const auto& g = k.gauss_markov;
        if (&m != best_gm) {
          line(fmt::format("# {} (score {:.3f}): gm-sigma = \"{:.6g},{:.6g},{:.6g}\" gm-tau = \"{:.6g},{:.6g},{:.6g}\"",
                           model_label(k), m.score, g[0].sigma_m, g[1].sigma_m, g[2].sigma_m, g[0].tau_s,
                           g[1].tau_s, g[2].tau_s));
          break;
        }
        line(fmt::format("gm-order = {}", k.gauss_markov_order));
        line(fmt::format("gm-sigma = \"{:.6g},{:.6g},{:.6g}\"", g[0].sigma_m, g[1].sigma_m, g[2].sigma_m));
        line(fmt::format("gm-tau = \"{:.6g},{:.6g},{:.6g}\"", g[0].tau_s, g[1].tau_s, g[2].tau_s));
        break;
      }
      case noise::Model::none: break;
    }
  }
  if (!c.cgrw_unusable.empty()) line(fmt::format("# cgrw not calibrated: {}", c.cgrw_unusable));
  return out;
}

}  // namespace gpsemu::calibration
