#include "emulator/calibration/report.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "emulator/calibration/calibrate.hpp"
#include "emulator/model/noise/gauss_markov_model.hpp"

namespace gpsemu::calibration {
namespace {

const char* const kAxes[3] = {"east", "north", "up"};

std::string scores_line(const Calibration& c) {
  std::string out = "score (mean |ln(model/real)| over every statistic and axis; 0 = identical, 0.22 = "
                    "25% off on average):";
  for (std::size_t i = 0; i < c.models.size(); ++i)
    out += fmt::format("  {}{} {:.3f}", i == c.best ? "*" : "", model_label(c.models[i].config),
                       c.models[i].score);
  return out + "\n";
}

std::string cell(std::optional<double> v) {
  if (!v || std::isnan(*v)) return "-";
  return fmt::format("{:.4g}", *v);
}

// The composite model's parameters, which smooth part won (both scores), and each component's
// share of the position variance and of the first-difference variance (expected values at the
// log's rate; jumps that never decay are counted over the log's duration; a cgrw smooth part's
// is the simulated total less the jitter's and jumps').
std::string composite_lines(const Calibration& c, const ModelResult& m) {
  const noise::NoiseConfig& k = m.config;
  const EnuSeries& s = c.series;
  const bool cgrw = k.composite.smooth == noise::CompositeSmooth::cgrw;
  std::string out = fmt::format("composite: {}\n", c.composite.describe());
  out += cgrw ? "composite (smooth cgrw W m, W1 m, W2 m, S2 m; jitter m; jumps /s, m, decay s):"
              : "composite (smooth gauss-markov-2 sigma m, tau s; jitter m; jumps /s, m, decay s):";
  const std::array<const noise::CgrwAxis*, 3> walk{&k.cgrw.east, &k.cgrw.north, &k.cgrw.up};
  for (std::size_t a = 0; a < 3; ++a) {
    const auto& g = k.composite.smooth_gm[a];
    const auto& x = k.composite.axes[a];
    out += cgrw ? fmt::format("  {} {:.4f}, {:.4f}, {:.4f}, {:.4f}", kAxes[a], walk[a]->width_m, walk[a]->width_d1_m,
                              walk[a]->width_d2_m, walk[a]->sigma_d2_m)
                : fmt::format("  {} {:.4f}, {:.1f}", kAxes[a], g.sigma_m, g.tau_s);
    out += fmt::format("; {:.4f}; {:.4f}, {:.3f}, {:.0f}", x.jitter_sigma_m, x.jump_rate_hz, x.jump_sigma_m,
                       x.jump_decay_s);
  }
  out += "\ncomposite shares (smooth / jitter / jumps) of the variance | of the first-difference variance:";
  const double dt = 1.0 / s.rate_hz;
  for (std::size_t a = 0; a < 3; ++a) {
    const auto& g = k.composite.smooth_gm[a];
    const auto& x = k.composite.axes[a];
    const double jump2 = x.jump_rate_hz * x.jump_sigma_m * x.jump_sigma_m;
    double var[3] = {g.sigma_m * g.sigma_m, x.jitter_sigma_m * x.jitter_sigma_m,
                     jump2 * (x.jump_decay_s > 0.0 ? x.jump_decay_s : s.duration_s()) / 2.0};
    double d1[3] = {2.0 * var[0] * (1.0 - noise::gauss_markov_autocorrelation(2, dt, g.tau_s)), 2.0 * var[1],
                    jump2 * dt};
    if (cgrw) {
      const double sd = m.stats[a].sd_m, d1_sd = m.stats[a].d1_sd_m;
      var[0] = std::max(0.0, sd * sd - var[1] - var[2]);
      d1[0] = std::max(0.0, d1_sd * d1_sd - d1[1] - d1[2]);
    }
    const double tv = var[0] + var[1] + var[2], td = d1[0] + d1[1] + d1[2];
    const auto pc = [](double v, double t) { return t > 0.0 ? 100.0 * v / t : 0.0; };
    out += fmt::format("  {} {:.0f}/{:.0f}/{:.0f}% | {:.0f}/{:.0f}/{:.0f}%", kAxes[a], pc(var[0], tv), pc(var[1], tv),
                       pc(var[2], tv), pc(d1[0], td), pc(d1[1], td), pc(d1[2], td));
  }
  return out + "\n";
}

}  // namespace

std::string log_summary(const Calibration& c, const std::string& path) {
  const EnuSeries& s = c.series;
  const LogCounts& n = c.counts;
  std::string out = fmt::format("log {}\n", path);
  out += fmt::format("  {} fixes on a {} Hz grid over {:.0f} s ({} epochs missing); resolution {} decimals "
                     "of minutes; mean position {:.8f}, {:.8f}, {:.2f} m\n",
                     s.size() - n.missing_epochs, s.rate_hz, s.duration_s(), n.missing_epochs,
                     s.minute_decimals, s.centre.lat_deg, s.centre.lon_deg, s.centre.alt_m);
  out += fmt::format("  skipped: {} GGA without fix, {} malformed GGA, {} repeated times; stream: {} "
                     "sentences ok, {} bad checksums, {} malformed, {} binary/garbage bytes, {} comment "
                     "lines\n",
                     n.gga_no_fix, n.gga_malformed, n.repeated_time, n.stream.sentences_ok,
                     n.stream.bad_checksum, n.stream.malformed, n.stream.garbage_bytes,
                     n.stream.comment_lines);
  for (const std::string& note : c.notes) out += fmt::format("  note: {}\n", note);
  return out;
}

std::string calibration_summary(const Calibration& c) {
  std::string out;
  out += fmt::format("cgrw statistics at {} Hz over windows of {} samples, measured -> best fit of the walk\n",
                     c.series.rate_hz, c.window_samples);
  out += fmt::format("  {:<6} {:>9} {:>9} {:>9} {:>9}   {:>9} {:>9} {:>9} {:>9}  {}\n", "axis", "W (m)",
                     "W1 (m)", "W2 (m)", "S2 (m)", "fit W", "fit W1", "fit W2", "fit S2", "fit/measured");
  for (std::size_t a = 0; a < 3; ++a) {
    const auto& m = c.cgrw_measured[a];
    const auto& f = c.cgrw_fit[a].achieved;
    out += fmt::format("  {:<6} {:9.4f} {:9.4f} {:9.4f} {:9.4f}   {:9.4f} {:9.4f} {:9.4f} {:9.4f}  "
                       "{:.2f} {:.2f} {:.2f} {:.2f}{}\n",
                       kAxes[a], m.width_m, m.width_d1_m, m.width_d2_m, m.sigma_d2_m, f.width_m,
                       f.width_d1_m, f.width_d2_m, f.sigma_d2_m, f.width_m / m.width_m,
                       f.width_d1_m / m.width_d1_m, f.width_d2_m / m.width_d2_m,
                       f.sigma_d2_m / m.sigma_d2_m,
                       c.cgrw_fit[a].worst_ratio > noise::kCgrwMaxFitRatio ? "  (out of reach: compromise written)" : "");
  }
  if (!c.cgrw_unusable.empty()) out += fmt::format("  cgrw not usable: {}\n", c.cgrw_unusable);
  for (const ModelResult& m : c.models) {
    const auto& k = m.config;
    if (k.model == noise::Model::gaussian) {
      out += "gaussian (mean, sigma) m:";
      for (std::size_t a = 0; a < 3; ++a)
        out += fmt::format("  {} {:.3g}, {:.4f}", kAxes[a], k.gaussian[a].mean_m, k.gaussian[a].sigma_m);
      out += "\n";
    } else if (k.model == noise::Model::gauss_markov) {
      out += fmt::format("{} (sigma m, tau s):", model_label(k));
      for (std::size_t a = 0; a < 3; ++a)
        out += fmt::format("  {} {:.4f}, {:.1f}", kAxes[a], k.gauss_markov[a].sigma_m, k.gauss_markov[a].tau_s);
      out += "\n";
    } else if (k.model == noise::Model::chrono) {
      out += fmt::format("chrono (mean, sigma m/s^2, rate Hz, v_max m/s, a_max m/s^2): {:g}, {:.5g}, {}, {:.5g}, "
                         "{:.5g}\n", k.chrono.mean, k.chrono.sigma, k.chrono.update_rate_hz,
                         k.chrono.v_max_mps, k.chrono.a_max_mps2);
    } else if (k.model == noise::Model::composite) {
      out += composite_lines(c, m);
    }
  }
  return out + hold_summary(c.hold) + velocity_summary(c.velocity) + scores_line(c);
}

std::string comparison_table(const Calibration& c) {
  std::string out;
  for (std::size_t a = 0; a < 3; ++a) {
    out += fmt::format("{:<15} {:>10}", kAxes[a], "real");
    for (const ModelResult& m : c.models) out += fmt::format(" {:>12}", model_label(m.config));
    out += "\n";
    for (const StatDef& d : stat_defs()) {
      out += fmt::format("  {:<13} {:>10}", d.name, cell(d.show(c.real[a])));
      for (const ModelResult& m : c.models) out += fmt::format(" {:>12}", cell(d.show(m.stats[a])));
      out += "\n";
    }
    // The spread of the statistics the goal is stated in: 10th..90th percentile over the runs.
    for (const StatDef& d : stat_defs()) {
      if (d.name != "std (m)" && d.name != "d1 std (m)" && d.name != "d2 std (m)" && d.name != "acf 10 s" &&
          d.name != "acf 30 s")
        continue;
      out += fmt::format("  p10..p90 {:<10} {:>7}", d.name.substr(0, d.name.find(" (m)")), "");
      for (const ModelResult& m : c.models) {
        const auto lo = d.show(m.low[a]), hi = d.show(m.high[a]);
        out += fmt::format(" {:>12}", lo && hi ? fmt::format("{:.3g}..{:.3g}", *lo, *hi) : std::string("-"));
      }
      out += "\n";
    }
  }
  out += scores_line(c);
  // Where each model falls short: statistics off by more than a factor 1.5.
  for (const ModelResult& m : c.models) {
    std::string misses;
    for (std::size_t a = 0; a < 3; ++a) {
      for (const StatDef& d : stat_defs()) {
        const auto r = d.get(c.real[a]), v = d.get(m.stats[a]);
        if (!r || !v || !(*r > 0) || !(*v > 0)) continue;
        const double ratio = *v / *r;
        if (ratio > 1.5 || ratio < 1 / 1.5)
          misses += fmt::format(" {} {} x{:.2g};", kAxes[a], d.name, ratio);
      }
    }
    out += fmt::format("  {} off by more than x1.5:{}\n", model_label(m.config),
                       misses.empty() ? " nothing" : misses);
  }
  out += "  (acf rows: the ratio is of 1 - autocorrelation)\n";
  out += hold_summary(c.hold);
  out += velocity_summary(c.velocity);
  for (const ModelResult& m : c.models)
    if (m.config.model == noise::Model::composite) out += composite_lines(c, m);
  return out;
}

void write_csv(const Calibration& c, const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error(fmt::format("--csv: cannot write '{}'", path));
  f << "t_s,real_east_m,real_north_m,real_up_m";
  for (const ModelResult& m : c.models) {
    const std::string name = model_label(m.config);
    f << "," << name << "_east_m," << name << "_north_m," << name << "_up_m";
  }
  f << "\n";
  const auto value = [](double v) { return std::isnan(v) ? std::string() : fmt::format("{:.4f}", v); };
  for (std::size_t k = 0; k < c.series.size(); ++k) {
    f << fmt::format("{:.3f}", static_cast<double>(k) / c.series.rate_hz);
    for (std::size_t a = 0; a < 3; ++a) f << "," << value(c.series.axis_m[a][k]);
    for (const ModelResult& m : c.models)
      for (std::size_t a = 0; a < 3; ++a) f << "," << value(m.first_run_m[a][k]);
    f << "\n";
  }
}

}  // namespace gpsemu::calibration
