#include "emulator/calibration/calibrate.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "emulator/calibration/model_fits.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/noise/cgrw_model.hpp"
#include "emulator/model/noise/gauss_markov_model.hpp"
#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::calibration {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// An axis whose fixes span less than this is constant (a receiver that holds its altitude: the
// east/north offsets still give its up coordinate nanometres of curvature): no noise on it.
constexpr double kConstantAxisRange_m = 1e-3;

std::array<AxisStats, 3> measure_all(const std::array<std::vector<double>, 3>& x, double rate_hz,
                                     std::size_t window) {
  return {measure_axis(x[0], rate_hz, window), measure_axis(x[1], rate_hz, window),
          measure_axis(x[2], rate_hz, window)};
}

// The cgrw-* keys of `p`, each line prefixed (a comment when `prefix` starts with '#').
std::string cgrw_keys(const noise::CgrwParams& p, const std::string& prefix) {
  std::string out;
  const std::array<const noise::CgrwAxis*, 3> axes{&p.east, &p.north, &p.up};
  for (std::size_t a = 0; a < 3; ++a)
    out += fmt::format("{}cgrw-{} = \"{:.6g},{:.6g},{:.6g},{:.6g}\"\n", prefix, kAxisNames[a], axes[a]->width_m,
                       axes[a]->width_d1_m, axes[a]->width_d2_m, axes[a]->sigma_d2_m);
  return out + fmt::format("{}cgrw-rate = {}\n{}cgrw-window = {:.6g}\n", prefix, p.rate_hz, prefix, p.window_s);
}

}  // namespace

std::string Calibration::CompositeChoice::describe() const {
  const std::string cgrw = std::isfinite(cgrw_score) ? fmt::format("{:.3f}", cgrw_score) : "not fitted";
  return fmt::format("smooth part {} (score with gauss-markov-2 {:.3f}, with cgrw {})", smooth, gm2_score, cgrw);
}

void for_each_run(std::size_t runs, const std::function<void(std::size_t)>& run) {
  const std::size_t threads = std::min<std::size_t>(runs, std::max(1U, std::thread::hardware_concurrency()));
  if (threads <= 1) {
    for (std::size_t r = 0; r < runs; ++r) run(r);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::exception_ptr failed;
  std::mutex failed_mutex;
  const auto worker = [&] {
    for (std::size_t r = next++; r < runs; r = next++) {
      try {
        run(r);
      } catch (...) {
        const std::lock_guard lock(failed_mutex);
        if (!failed) failed = std::current_exception();
      }
    }
  };
  {
    std::vector<std::jthread> pool;
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
  }
  if (failed) std::rethrow_exception(failed);
}

std::array<AxisStats, 3> simulated_stats(const noise::NoiseConfig& config, const EnuSeries& series,
                                         std::size_t window, std::uint64_t seed, int runs,
                                         std::array<std::vector<double>, 3>* first_run,
                                         std::array<std::vector<AxisStats>, 3>* per_run,
                                         const StaticHoldOptions& hold) {
  std::vector<std::array<AxisStats, 3>> stats(static_cast<std::size_t>(std::max(runs, 0)));
  std::array<std::vector<double>, 3> first;
  for_each_run(stats.size(), [&](std::size_t r) {
    auto x = simulate(config, series, seed + static_cast<std::uint64_t>(r), hold);
    stats[r] = measure_all(x, series.rate_hz, window);
    if (r == 0 && first_run) first = std::move(x);
  });
  std::array<std::vector<AxisStats>, 3> per_axis;
  for (const auto& s : stats)
    for (std::size_t a = 0; a < 3; ++a) per_axis[a].push_back(s[a]);
  if (first_run) *first_run = std::move(first);
  std::array<AxisStats, 3> mean{mean_stats(per_axis[0]), mean_stats(per_axis[1]), mean_stats(per_axis[2])};
  if (per_run) *per_run = std::move(per_axis);
  return mean;
}

std::array<std::vector<double>, 3> simulate(const noise::NoiseConfig& config, const EnuSeries& series,
                                            std::uint64_t seed, const StaticHoldOptions& hold_options) {
  auto model = noise::make_noise_model(config, seed);
  const LocalFrame frame(series.centre);
  nmea::FormatOptions format;
  format.minute_decimals = std::clamp(series.minute_decimals, 1, 8);
  format.alt_decimals = std::clamp(series.alt_decimals, 0, 4);
  StaticHold hold(hold_options);
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
    if (std::isnan(series.axis_m[0][k])) {
      hold.reset();
      continue;
    }
    const Geodetic g = frame.to_geodetic(hold.apply(e, 0.0));
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

std::size_t max_epochs_for_memory(std::uint64_t available_bytes) {
  return static_cast<std::size_t>(
      std::min<std::uint64_t>(available_bytes / 2 / kCalibrationBytesPerEpoch, kMaxCalibrationEpochs));
}

Calibration calibrate(ReceiverLog log, const CalibrateOptions& options) {
  if (options.runs < 1) throw std::invalid_argument("runs must be >= 1");
  Calibration c;
  c.series = to_enu_series(log, options.max_epochs, options.max_epochs_reason);
  c.counts = log.counts;
  EnuSeries& s = c.series;
  c.window_samples = std::min<std::size_t>(s.size(), static_cast<std::size_t>(noise::kCgrwMaxWindowSamples));
  c.motion = check_motion(s, log.speeds);
  c.velocity = fit_velocity(log.speeds, s.rate_hz > 0 ? 1.0 / s.rate_hz : 1.0, options.seed);
  if (options.detrend) {
    const Detrended d = detrend(s);
    c.notes.push_back(fmt::format("detrended: a smooth trajectory (local quadratic over {:.0f} s) removed first: "
                                  "{:.2f} m rms from the mean, {:.1f} m of path (the log: {}); the noise's own wander slower "
                                  "than that went with it: sd and slow part are under-estimated",
                                  kDetrendWindow_s, d.rms_m, d.path_m, c.motion.describe()));
  } else if (c.motion.moving) {
    throw MotionError(fmt::format("the log moves: {}; {}. Calibration needs a stationary receiver (--detrend "
                                  "removes a smooth trajectory first)",
                                  c.motion.describe(), c.motion.describe_limits()));
  }
  for (std::size_t a = 0; a < 3; ++a) {
    const double range_m = measure_axis(s.axis_m[a], s.rate_hz, c.window_samples).range_m;
    if (range_m >= kConstantAxisRange_m) continue;
    for (double& v : s.axis_m[a])
      if (!std::isnan(v)) v = 0.0;
    c.notes.push_back(fmt::format("{}: constant (fixes span {:.2g} m): no noise on this axis", kAxisNames[a], range_m));
  }
  c.real = measure_all(s.axis_m, s.rate_hz, c.window_samples);
  if (c.real[0].sd_m <= 0.0 && c.real[1].sd_m <= 0.0)
    throw std::invalid_argument("the log's horizontal position never changes: nothing to calibrate");

  // cgrw: the report's four statistics over the log's length at its rate.
  noise::NoiseConfig cgrw;
  cgrw.model = noise::Model::cgrw;
  try {
    for (std::size_t a = 0; a < 3; ++a) c.cgrw_measured[a] = c.real[a].cgrw;
    cgrw.cgrw = fit_cgrw_dequantised(s, c.real, c.window_samples, c.cgrw_fit, c.notes);
    (void)noise::make_noise_model(cgrw, 1);  // the emulator must accept what is written
  } catch (const std::exception& e) {
    c.cgrw_unusable = e.what();
  }

  noise::NoiseConfig chrono;
  chrono.model = noise::Model::chrono;
  chrono.chrono = fit_chrono(s, c.real);

  noise::NoiseConfig gaussian;
  gaussian.model = noise::Model::gaussian;
  for (std::size_t a = 0; a < 3; ++a) {
    double mean = 0.0, n = 0.0;
    for (double v : s.axis_m[a])
      if (!std::isnan(v)) mean += v, n += 1;
    gaussian.gaussian[a] = {mean / n, c.real[a].sd_m};
  }
  noise::NoiseConfig gm1, gm2;
  gm1.model = gm2.model = noise::Model::gauss_markov;
  gm1.gauss_markov_order = 1;
  gm2.gauss_markov_order = 2;
  gm1.gauss_markov = fit_gauss_markov_dequantised(s, c.real, c.window_samples, 1);
  gm2.gauss_markov = fit_gauss_markov_dequantised(s, c.real, c.window_samples, 2);

  std::vector<noise::NoiseConfig> configs;
  if (c.cgrw_unusable.empty()) configs.push_back(cgrw);
  configs.push_back(chrono);
  configs.push_back(gaussian);
  configs.push_back(gm1);
  configs.push_back(gm2);
  configs.push_back(fit_composite(s, c.real, c.window_samples, &c.notes, {}, options.runs));
  c.composite.cgrw_score = std::numeric_limits<double>::infinity();
  try {
    configs.push_back(fit_composite_cgrw(s, c.real, c.window_samples, &c.notes, options.runs));
    (void)noise::make_noise_model(configs.back(), 1);
  } catch (const std::exception& e) {
    if (configs.back().model == noise::Model::composite && configs.back().composite.smooth == noise::CompositeSmooth::cgrw)
      configs.pop_back();
    c.notes.push_back(fmt::format("composite with a cgrw smooth part not fitted: {}", e.what()));
  }
  // Each model's median, 10th and 90th percentile over the runs and its score, simulated through `hold`.
  const auto run_model = [&](ModelResult& r, const StaticHoldOptions& hold) {
    std::array<std::vector<AxisStats>, 3> runs;
    (void)simulated_stats(r.config, s, c.window_samples, options.seed, options.runs, &r.first_run_m, &runs, hold);
    for (std::size_t a = 0; a < 3; ++a)
      r.stats[a] = quantile_stats(runs[a], 0.5), r.low[a] = quantile_stats(runs[a], 0.1),
      r.high[a] = quantile_stats(runs[a], 0.9);
    r.score = score(c.real, r.stats);
  };
  for (const noise::NoiseConfig& config : configs) {
    ModelResult r;
    r.config = config;
    run_model(r, {});
    c.models.push_back(std::move(r));
  }
  // Keep the better composite (the same score as every model), say which and both scores.
  if (configs.back().composite.smooth == noise::CompositeSmooth::cgrw) {
    const std::size_t gm2 = c.models.size() - 2, cgrw_smooth = c.models.size() - 1;
    c.composite.gm2_score = c.models[gm2].score, c.composite.cgrw_score = c.models[cgrw_smooth].score;
    const bool cgrw_wins = c.composite.cgrw_score < c.composite.gm2_score;
    c.composite.smooth = cgrw_wins ? "cgrw" : "gauss-markov-2";
    c.models.erase(c.models.begin() + static_cast<std::ptrdiff_t>(cgrw_wins ? gm2 : cgrw_smooth));
  } else {
    c.composite.gm2_score = c.models.back().score;
  }
  for (std::size_t i = 1; i < c.models.size(); ++i)
    if (c.models[i].score < c.models[c.best].score) c.best = i;
  c.hold = fit_hold(s, c.models[c.best].config, options.seed, options.runs);
  if (c.hold.hold.enabled()) {
    // What the emulator runs with the calibrated config: the composite refitted through the hold
    // (with a gauss-markov-2 smooth part), the hold fitted again if it is the best, and
    // every model simulated through the hold and scored again (issue 27: compare and judge
    // simulated without it, and a smooth wander through the hold has larger steps than without).
    const auto composite = std::find_if(c.models.begin(), c.models.end(), [](const ModelResult& m) {
      return m.config.model == noise::Model::composite;
    });
    ModelResult unheld_fit;  // the composite fitted without the hold, kept if it scores better through it
    if (composite != c.models.end()) {
      unheld_fit = *composite;
      std::vector<std::string> held_notes;
      composite->config = fit_composite(s, c.real, c.window_samples, &held_notes, c.hold.hold, options.runs);
      for (const std::string& note : held_notes) c.notes.push_back("through the static hold: " + note);
      if (composite - c.models.begin() == static_cast<std::ptrdiff_t>(c.best))
        c.hold = fit_hold(s, composite->config, options.seed, options.runs);
    }
    const std::string fitted_for = model_label(c.models[c.best].config);
    for (ModelResult& r : c.models) run_model(r, c.hold.hold);
    if (composite != c.models.end()) {
      run_model(unheld_fit, c.hold.hold);
      const bool keep_unheld = unheld_fit.score < composite->score;
      c.notes.push_back(fmt::format("composite through the static hold: fitted through it {:.3f}, fitted without it "
                                    "{:.3f}: {} kept", composite->score, unheld_fit.score,
                                    keep_unheld ? "the fit without it" : "the fit through it"));
      if (keep_unheld)
        *composite = std::move(unheld_fit);
      else
        c.composite.smooth = "gauss-markov-2";
    }
    c.best = 0;
    for (std::size_t i = 1; i < c.models.size(); ++i)
      if (c.models[i].score < c.models[c.best].score) c.best = i;
    c.notes.push_back(fmt::format("every model simulated through the static hold (radius {:.4g} m, fitted for {}) "
                                  "for its statistics and score", c.hold.hold.radius_m, fitted_for));
  }
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
  for (const std::string& note : c.notes) line("# " + note);
  line(fmt::format("noise = \"{}\"", noise::to_string(c.models[c.best].config.model)));
  line(fmt::format("rate = {}", s.rate_hz));
  line(fmt::format("resolution = {}", std::clamp(s.minute_decimals, 1, 8)));
  out += hold_toml(c.hold);
  out += velocity_toml(c.velocity);
  line(fmt::format("origin = \"{:.9f},{:.9f},{:.2f}\"", s.centre.lat_deg, s.centre.lon_deg, s.centre.alt_m));
  const ModelResult* best_gm = nullptr;  // the gauss-markov order whose keys are written
  for (const ModelResult& m : c.models)
    if (m.config.model == noise::Model::gauss_markov && (!best_gm || m.score < best_gm->score)) best_gm = &m;
  // The cgrw-* keys are always cgrw's own fit, so `--noise cgrw` with this file runs it (issue 27);
  // a composite with a cgrw smooth part writes its walk under composite-cgrw-* (it has its own
  // scale beside the slow part and jitter; the rate and window are the same).
  for (const ModelResult& m : c.models) {
    const noise::NoiseConfig& k = m.config;
    switch (k.model) {
      case noise::Model::cgrw: {
        for (std::size_t a = 0; a < 3; ++a) {
          if (c.cgrw_fit[a].worst_ratio > noise::kCgrwMaxFitRatio) {
            const auto& w = c.cgrw_measured[a];
            line(fmt::format("# cgrw {}: measured {:.6g},{:.6g},{:.6g},{:.6g} is out of the walk's reach "
                             "(best fit off by x{:.2f}); its best compromise is written", kAxisNames[a],
                             w.width_m, w.width_d1_m, w.width_d2_m, w.sigma_d2_m, c.cgrw_fit[a].worst_ratio));
          }
        }
        out += cgrw_keys(k.cgrw, "");
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
      case noise::Model::composite: {
        line(fmt::format("# composite: {}", c.composite.describe()));
        const auto& g = k.composite.smooth_gm;
        const auto& x = k.composite.axes;
        const auto three = [](double a, double b, double c) { return fmt::format("\"{:.6g},{:.6g},{:.6g}\"", a, b, c); };
        if (k.composite.smooth == noise::CompositeSmooth::cgrw) {
          line("composite-smooth = \"cgrw\"");
          const std::array<const noise::CgrwAxis*, 3> walk{&k.cgrw.east, &k.cgrw.north, &k.cgrw.up};
          for (std::size_t a = 0; a < 3; ++a)
            line(fmt::format("composite-cgrw-{} = \"{:.6g},{:.6g},{:.6g},{:.6g}\"", kAxisNames[a], walk[a]->width_m,
                             walk[a]->width_d1_m, walk[a]->width_d2_m, walk[a]->sigma_d2_m));
        } else {
          line("composite-smooth = \"gauss-markov-2\"");
          line("composite-sigma = " + three(g[0].sigma_m, g[1].sigma_m, g[2].sigma_m));
          line("composite-tau = " + three(g[0].tau_s, g[1].tau_s, g[2].tau_s));
        }
        line("composite-jitter = " + three(x[0].jitter_sigma_m, x[1].jitter_sigma_m, x[2].jitter_sigma_m));
        line("composite-jump-rate = " + three(x[0].jump_rate_hz, x[1].jump_rate_hz, x[2].jump_rate_hz));
        line("composite-jump-size = " + three(x[0].jump_sigma_m, x[1].jump_sigma_m, x[2].jump_sigma_m));
        line("composite-jump-decay = " + three(x[0].jump_decay_s, x[1].jump_decay_s, x[2].jump_decay_s));
        if (x[0].slow_sigma_m > 0.0 || x[1].slow_sigma_m > 0.0 || x[2].slow_sigma_m > 0.0) {
          line("composite-slow-sigma = " + three(x[0].slow_sigma_m, x[1].slow_sigma_m, x[2].slow_sigma_m));
          line("composite-slow-tau = " + three(x[0].slow_tau_s > 0.0 ? x[0].slow_tau_s : 1.0,
                                               x[1].slow_tau_s > 0.0 ? x[1].slow_tau_s : 1.0,
                                               x[2].slow_tau_s > 0.0 ? x[2].slow_tau_s : 1.0));
        }
        break;
      }
      case noise::Model::none: break;
    }
  }
  if (!c.cgrw_unusable.empty()) line(fmt::format("# cgrw not calibrated: {}", c.cgrw_unusable));
  return out;
}

}  // namespace gpsemu::calibration
