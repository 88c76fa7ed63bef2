#include "emulator/calibration/hold_fit.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "emulator/calibration/calibrate.hpp"

namespace gpsemu::calibration {
namespace {

// The mean repeated share of `runs` simulations of `config` with `hold`.
double simulated_share(const noise::NoiseConfig& config, const EnuSeries& s, std::uint64_t seed, int runs,
                       const StaticHoldOptions& hold) {
  std::vector<double> share(static_cast<std::size_t>(std::max(runs, 0)));
  for_each_run(share.size(), [&](std::size_t r) {
    share[r] = repeat_share(simulate(config, s, seed + static_cast<std::uint64_t>(r), hold));
  });
  double sum = 0.0;
  for (const double x : share) sum += x;  // in the runs' order, whatever the threads
  return sum / runs;
}

}  // namespace

double repeat_share(const std::array<std::vector<double>, 3>& x) {
  std::size_t pairs = 0, repeats = 0;
  for (std::size_t k = 1; k < x[0].size(); ++k) {
    if (std::isnan(x[0][k]) || std::isnan(x[0][k - 1])) continue;
    ++pairs;
    if (x[0][k] == x[0][k - 1] && x[1][k] == x[1][k - 1]) ++repeats;
  }
  return pairs ? static_cast<double>(repeats) / static_cast<double>(pairs) : 0.0;
}

HoldFit fit_hold(const EnuSeries& s, const noise::NoiseConfig& best, std::uint64_t seed, int runs) {
  HoldFit f;
  f.alt_decimals = s.alt_decimals;
  f.real_share = repeat_share(s.axis_m);
  runs = std::clamp(runs, 1, 8);
  f.model_share = f.held_share = simulated_share(best, s, seed, runs, {});
  if (f.real_share < f.model_share + kHoldMinExcessShare) return f;
  // The repeated share grows with the radius: bisect on its logarithm, from a thousandth of the
  // model's horizontal first difference (nothing held) to 20x the log's horizontal spread.
  double sd_h = 0.0, d1_h = 0.0, n = 0.0, mean_e = 0.0, mean_n = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k)
    if (!std::isnan(s.axis_m[0][k])) mean_e += s.axis_m[0][k], mean_n += s.axis_m[1][k], n += 1.0;
  mean_e /= n, mean_n /= n;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (std::isnan(s.axis_m[0][k])) continue;
    sd_h += std::pow(s.axis_m[0][k] - mean_e, 2) + std::pow(s.axis_m[1][k] - mean_n, 2);
    if (k > 0 && !std::isnan(s.axis_m[0][k - 1]))
      d1_h = std::max(d1_h, std::hypot(s.axis_m[0][k] - s.axis_m[0][k - 1], s.axis_m[1][k] - s.axis_m[1][k - 1]));
  }
  sd_h = std::sqrt(sd_h / n);
  double lo = std::log(std::max(1e-4, 1e-3 * std::max(d1_h, sd_h))), hi = std::log(std::max(20.0 * sd_h, 1e-3));
  double best_error = 1e9;
  for (int i = 0; i < 14; ++i) {
    const double mid = 0.5 * (lo + hi);
    const StaticHoldOptions h{std::exp(mid), kCalibratedHoldSpeed_mps};
    const double share = simulated_share(best, s, seed, runs, h);
    if (std::abs(share - f.real_share) < best_error) best_error = std::abs(share - f.real_share), f.hold = h, f.held_share = share;
    (share < f.real_share ? lo : hi) = mid;
  }
  f.radius_at_bound = f.held_share < f.real_share - kHoldMinExcessShare && f.hold.radius_m >= 0.9 * 20.0 * sd_h;
  return f;
}

std::string hold_toml(const HoldFit& f) {
  std::string out = fmt::format("# altitude written with {} decimals in the log\nalt-decimals = {}\n", f.alt_decimals,
                                std::clamp(f.alt_decimals, 0, 4));
  out += fmt::format("# repeated positions: the log {:.0f}% of epochs, the best model {:.0f}% by its resolution alone",
                     100 * f.real_share, 100 * f.model_share);
  if (!f.hold.enabled()) return out + ": no static hold\n";
  out += fmt::format(", {:.0f}% with the hold below{}\n", 100 * f.held_share,
                     f.radius_at_bound ? " (radius at its bound, 20x the log's spread)" : "");
  out += fmt::format("# hold-speed is not learnt from a stationary log (it never moves): {} m/s\n", f.hold.max_speed_mps);
  return out + fmt::format("hold-radius = {:.4g}\nhold-speed = {}\n", f.hold.radius_m, f.hold.max_speed_mps);
}

std::string hold_summary(const HoldFit& f) {
  std::string out = fmt::format("static hold: the log repeats its previous position in {:.1f}% of epochs, the best "
                                "model {:.1f}% by its resolution alone", 100 * f.real_share, 100 * f.model_share);
  if (f.hold.enabled())
    out += fmt::format("; hold radius {:.4g} m (below {} m/s): {:.1f}%{}", f.hold.radius_m, f.hold.max_speed_mps,
                       100 * f.held_share, f.radius_at_bound ? " (radius at its bound)" : "");
  else
    out += ": no hold";
  return out + fmt::format("; altitude decimals {}\n", f.alt_decimals);
}

}  // namespace gpsemu::calibration
