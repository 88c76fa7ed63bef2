#include "emulator/calibration/judge.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "emulator/model/noise/sample_stats.hpp"
#include "emulator/model/receiver.hpp"

namespace gpsemu::calibration {
namespace {

// One axis of the constant-velocity filter.
struct Axis {
  double p = 0.0, v = 0.0;
  double P00 = 0.0, P01 = 0.0, P11 = 0.0;
  void predict(double dt, double q) {
    p += v * dt;
    const double n00 = P00 + 2.0 * dt * P01 + dt * dt * P11 + q * dt * dt * dt / 3.0;
    const double n01 = P01 + dt * P11 + q * dt * dt / 2.0;
    P11 += q * dt;
    P00 = n00, P01 = n01;
  }
  // Returns (innovation, its variance) and updates.
  std::pair<double, double> update(double z, double r) {
    const double nu = z - p, s = P00 + r;
    const double k0 = P00 / s, k1 = P01 / s;
    p += k0 * nu, v += k1 * nu;
    const double n00 = (1.0 - k0) * P00, n01 = (1.0 - k0) * P01, n11 = P11 - k1 * P01;
    P00 = n00, P01 = n01, P11 = n11;
    return {nu, s};
  }
};

double lag1(const std::vector<double>& x) {
  double m = 0.0;
  for (double v : x) m += v / static_cast<double>(x.size());
  double num = 0.0, den = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    den += (x[k] - m) * (x[k] - m);
    if (k > 0) num += (x[k] - m) * (x[k - 1] - m);
  }
  return den > 0.0 ? num / den : 0.0;
}

double percentile95(std::vector<double> x) { return noise::quantile(std::move(x), 0.95); }

double log_ratio(double a, double b) { return a > 0.0 && b > 0.0 ? std::abs(std::log(a / b)) : 1.0; }

nlohmann::json to_json(const FilterScore& s) {
  return {{"nis_mean", s.nis_mean}, {"nis_p95", s.nis_p95}, {"innov_rho1", s.innov_rho1}, {"pos_err_m", s.pos_err_m}};
}

}  // namespace

FilterScore run_cv_filter(const std::vector<double>& east_m, const std::vector<double>& north_m, double rate_hz,
                          double sigma_m, double q) {
  const double r = sigma_m * sigma_m, dt = 1.0 / rate_hz;
  const std::size_t n = east_m.size();
  double me = 0.0, mn = 0.0, count = 0.0;
  for (std::size_t k = 0; k < n; ++k)
    if (!std::isnan(east_m[k]) && !std::isnan(north_m[k])) me += east_m[k], mn += north_m[k], count += 1.0;
  me /= count, mn /= count;
  std::array<Axis, 2> axes;
  std::array<std::vector<double>, 2> innov;
  FilterScore s;
  double err2 = 0.0, err_n = 0.0;
  bool started = false;
  double since_s = 0.0, gap_s = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (std::isnan(east_m[k]) || std::isnan(north_m[k])) {
      gap_s += dt;
      continue;
    }
    const double z[2] = {east_m[k], north_m[k]};
    if (!started) {
      for (int a = 0; a < 2; ++a) axes[a] = {z[a], 0.0, r, 0.0, 1.0};
      started = true, gap_s = 0.0;
      continue;
    }
    const double step = dt + gap_s;
    gap_s = 0.0;
    since_s += step;
    double nis = 0.0;
    std::array<double, 2> normalised{};
    for (int a = 0; a < 2; ++a) {
      axes[a].predict(step, q);
      const auto [nu, var] = axes[a].update(z[a], r);
      nis += nu * nu / var;
      normalised[a] = nu / std::sqrt(var);
    }
    if (since_s < kJudgeBurnIn_s) continue;
    s.nis.push_back(nis);
    for (int a = 0; a < 2; ++a) innov[a].push_back(normalised[a]);
    err2 += (axes[0].p - me) * (axes[0].p - me) + (axes[1].p - mn) * (axes[1].p - mn), err_n += 1.0;
  }
  if (s.nis.empty()) throw std::invalid_argument("judge: the log is shorter than the filter's burn-in");
  for (double v : s.nis) s.nis_mean += v / static_cast<double>(s.nis.size());
  s.nis_p95 = percentile95(s.nis);
  s.innov_rho1 = 0.5 * (lag1(innov[0]) + lag1(innov[1]));
  s.pos_err_m = std::sqrt(err2 / err_n);
  return s;
}

double stated_sigma_m(const ReceiverLog& log, const Calibration& c) {
  std::vector<double> hdop;
  for (const LogFix& f : log.fixes)
    if (f.hdop && *f.hdop > 0.0) hdop.push_back(*f.hdop);
  if (hdop.empty()) return std::hypot(c.real[0].sd_m, c.real[1].sd_m) / std::sqrt(2.0);
  std::nth_element(hdop.begin(), hdop.begin() + static_cast<std::ptrdiff_t>(hdop.size() / 2), hdop.end());
  return hdop[hdop.size() / 2] * kUereM / std::sqrt(2.0);
}

namespace {

// Each score's `q` quantile over runs, each on its own (nearest rank below).
FilterScore quantile_score(std::vector<FilterScore> runs, double q) {
  FilterScore out;
  if (runs.empty()) return out;
  const auto pick = [&](double FilterScore::*field) {
    std::vector<double> v;
    for (const FilterScore& r : runs) v.push_back(r.*field);
    out.*field = noise::quantile(std::move(v), q);
  };
  pick(&FilterScore::nis_mean), pick(&FilterScore::nis_p95), pick(&FilterScore::innov_rho1), pick(&FilterScore::pos_err_m);
  return out;
}

// The distance's four terms of a model's scores from the real log's.
std::array<double, 4> distance_terms(const FilterScore& m, const FilterScore& real) {
  return {log_ratio(m.nis_mean, real.nis_mean), log_ratio(m.nis_p95, real.nis_p95), std::abs(m.innov_rho1 - real.innov_rho1),
          log_ratio(m.pos_err_m, real.pos_err_m)};
}

double distance_of(const FilterScore& m, const FilterScore& real) {
  const auto t = distance_terms(m, real);
  return t[0] + t[1] + t[2] + t[3];
}

}  // namespace

Judgement judge(const Calibration& c, double sigma_m, int runs, std::uint64_t seed) {
  Judgement j;
  j.sigma_m = sigma_m;
  const EnuSeries& s = c.series;
  j.real = run_cv_filter(s.axis_m[0], s.axis_m[1], s.rate_hz, sigma_m);
  double best = std::numeric_limits<double>::infinity();
  for (const ModelResult& m : c.models) {
    const std::string name = model_label(m.config);
    std::vector<FilterScore> all(static_cast<std::size_t>(std::max(runs, 0)));
    for_each_run(all.size(), [&](std::size_t r) {
      const auto x = simulate(m.config, s, seed + static_cast<std::uint64_t>(r), c.hold.hold);
      all[r] = run_cv_filter(x[0], x[1], s.rate_hz, sigma_m);
    });
    for (FilterScore& f : all) {
      j.model_nis[name].push_back(std::move(f.nis));
      f.nis.clear();
    }
    const FilterScore mean = quantile_score(all, 0.5);
    j.spread[name] = {quantile_score(all, 0.1), quantile_score(all, 0.9)};
    const double d = distance_of(mean, j.real);
    j.distance[name] = d;
    j.models[name] = mean;
    if (d < best) best = d, j.best = name;
  }
  return j;
}

std::string judgement_table(const Judgement& j) {
  std::string out = fmt::format(
      "constant-velocity Kalman filter, measurement sigma {:.3f} m per axis, process noise {:g} m^2/s^3; "
      "a filter whose model is right has NIS mean 2, p95 5.99, rho1 0\n",
      j.sigma_m, kJudgeProcessNoise_m2ps3);
  out += fmt::format("  {:<16} {:>9} {:>9} {:>11} {:>11} {:>9}\n", "", "NIS mean", "NIS p95", "innov rho1",
                     "pos err m", "distance");
  const auto row = [&out](const std::string& name, const FilterScore& s, std::string d) {
    out += fmt::format("  {:<16} {:9.3f} {:9.3f} {:11.3f} {:11.4f} {:>9}\n", name, s.nis_mean, s.nis_p95, s.innov_rho1,
                       s.pos_err_m, d);
  };
  row("real", j.real, "");
  for (const auto& [name, s] : j.models) {
    row((name == j.best ? "*" : "") + name, s, fmt::format("{:.3f}", j.distance.at(name)));
    const auto spread = j.spread.find(name);
    if (spread == j.spread.end()) continue;
    const FilterScore& lo = spread->second[0];
    const FilterScore& hi = spread->second[1];
    out += fmt::format("  {:<16} {:>9} {:>9} {:>11} {:>11}\n", "  p10..p90", fmt::format("{:.2f}..{:.2f}", lo.nis_mean, hi.nis_mean),
                       fmt::format("{:.2f}..{:.2f}", lo.nis_p95, hi.nis_p95),
                       fmt::format("{:.2f}..{:.2f}", lo.innov_rho1, hi.innov_rho1),
                       fmt::format("{:.3f}..{:.3f}", lo.pos_err_m, hi.pos_err_m));
  }
  out += "  models: the median over the runs (windows of the log's length) and the 10th..90th percentile below it\n";
  out += "  distance = |ln NIS mean ratio| + |ln NIS p95 ratio| + |rho1 difference| + |ln pos err ratio|; * = best\n";
  return out;
}

std::string disagreement(const Judgement& j, const Calibration& c) {
  const std::string stats_best = model_label(c.models[c.best].config);
  if (j.best.empty() || j.best == stats_best || !j.models.count(stats_best)) return "";
  static const char* const kTerms[4] = {"NIS mean", "NIS p95", "innovation rho1", "position error"};
  const auto t = distance_terms(j.models.at(stats_best), j.real);
  const auto worst = static_cast<std::size_t>(std::max_element(t.begin(), t.end()) - t.begin());
  const auto value = [&](const FilterScore& f) {
    const double v[4] = {f.nis_mean, f.nis_p95, f.innov_rho1, f.pos_err_m};
    return v[worst];
  };
  std::string out = fmt::format(
      "the judge and the statistics disagree: the statistics' best, {} (score {:.3f}), is {:.3f} from the real filter, "
      "most in its {} ({:.3g} against the real {:.3g}, {:.3g} for {});",
      stats_best, c.models[c.best].score, j.distance.at(stats_best), kTerms[worst], value(j.models.at(stats_best)),
      value(j.real), value(j.models.at(j.best)), j.best);
  // What the judge's best misses in the statistics: the largest ratios of its medians to the log's.
  for (const ModelResult& m : c.models) {
    if (model_label(m.config) != j.best) continue;
    std::vector<std::pair<double, std::string>> misses;
    for (std::size_t a = 0; a < 2; ++a)
      for (const StatDef& d : stat_defs()) {
        const auto r = d.get(c.real[a]), v = d.get(m.stats[a]);
        if (r && v && *r > 0.0 && *v > 0.0)
          misses.emplace_back(std::abs(std::log(*v / *r)),
                              fmt::format("{} {} x{:.2g}", a == 0 ? "east" : "north", d.name, *v / *r));
      }
    std::sort(misses.begin(), misses.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    out += fmt::format(" the judge's best, {} (score {:.3f}), misses", j.best, m.score);
    for (std::size_t i = 0; i < std::min<std::size_t>(3, misses.size()); ++i) out += (i ? ", " : " ") + misses[i].second;
    out += ". The filter sees only what a constant-velocity filter with the receiver's stated sigma sees (its NIS, "
           "innovation correlation and error); the score weighs every timescale of the position itself\n";
  }
  return out;
}

std::string judgement_json(const Judgement& j) {
  nlohmann::json models = nlohmann::json::object();
  for (const auto& [name, s] : j.models) {
    models[name] = to_json(s);
    models[name]["distance"] = j.distance.at(name);
  }
  const nlohmann::json out{{"real", to_json(j.real)}, {"models", models}, {"best", j.best}, {"sigma_m", j.sigma_m},
                           {"process_noise_m2ps3", kJudgeProcessNoise_m2ps3}};
  return out.dump(2) + "\n";
}

void write_judgement_csv(const Judgement& j, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const auto open = [&dir](const char* name) {
    const std::string path = (std::filesystem::path(dir) / name).string();
    std::ofstream f(path);
    if (!f) throw std::runtime_error(fmt::format("--plots: cannot write '{}'", path));
    return f;
  };
  std::ofstream nis = open("judge_nis.csv");
  nis << "source,run,nis\n";
  for (double v : j.real.nis) nis << "real,0," << v << "\n";
  for (const auto& [name, all] : j.model_nis)
    for (std::size_t r = 0; r < all.size(); ++r)
      for (double v : all[r]) nis << name << "," << r << "," << v << "\n";
  std::ofstream sum = open("judge_summary.csv");
  sum << "source,nis_mean,nis_p95,innov_rho1,pos_err_m,distance\n";
  const auto row = [&sum](const std::string& name, const FilterScore& s, double d) {
    sum << fmt::format("{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", name, s.nis_mean, s.nis_p95, s.innov_rho1, s.pos_err_m, d);
  };
  row("real", j.real, 0.0);
  for (const auto& [name, s] : j.models) row(name, s, j.distance.at(name));
  if (!nis.flush() || !sum.flush()) throw std::runtime_error(fmt::format("--plots: cannot write to '{}'", dir));
}

}  // namespace gpsemu::calibration
