// The composite noise model's options of the option table (docs/noise-and-calibration.md): its
// smooth part (gauss-markov-2 or its own cgrw walk), jitter, jumps and slow part, each one value
// for the three axes or one each. Kept apart from config_options.cpp (its size).
#include <algorithm>
#include <array>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/config/config_options.hpp"
#include "emulator/config/config_values.hpp"

namespace gpsemu {
namespace {

using V = const std::vector<std::string>&;
using namespace config_values;

// "X[,XN,XU]": one value for the three axes or one each, every one >= `min` (> 0 when `positive`).
std::array<double, 3> parse_per_axis(const std::string& key, const std::string& text, bool positive, const char* unit) {
  const auto x = parse_list(key, text, 1, 3);
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    out[i] = x[std::min(i, x.size() - 1)];
    if (positive ? !(out[i] > 0.0) : !(out[i] >= 0.0))
      throw std::invalid_argument(fmt::format("{} must be {} {}, got '{}'", key, positive ? "> 0" : ">= 0", unit, text));
  }
  return out;
}

}  // namespace

void add_composite_options(std::vector<OptionDef>& t) {
  const auto add = [&t](std::string name, std::string value_name, std::string help,
                        std::function<void(ConfigDraft&, V)> apply) {
    t.push_back({std::move(name), std::move(value_name), std::move(help), OptionScope::receiver, false, std::move(apply)});
  };
  add("composite-smooth", "KIND", "composite model's smooth component: gauss-markov-2 (composite-sigma, "
      "composite-tau) | cgrw (composite-cgrw-*, else the cgrw-* keys) (default gauss-markov-2)",
      [](ConfigDraft& d, V v) {
        d.receiver.settings.noise.composite.smooth = parse_choice("composite-smooth", v.back(), {"gauss-markov-2", "cgrw"}) == "cgrw"
                                                         ? noise::CompositeSmooth::cgrw
                                                         : noise::CompositeSmooth::gauss_markov_2;
      });
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string axis = i == 0 ? "east" : i == 1 ? "north" : "up";
    add("composite-cgrw-" + axis, "W,W1,W2,S2",
        fmt::format("composite model with composite-smooth cgrw: its walk's {} axis, as cgrw-{} (at cgrw-rate, "
                    "over cgrw-window); all three axes or none (default: the cgrw-* keys)", axis, axis),
        [i, axis](ConfigDraft& d, V v) {
          d.receiver.composite_cgrw[i] = parse_cgrw_axis("composite-cgrw-" + axis, v.back());
        });
  }
  add("composite-sigma", "S[,SN,SU]", "composite model: smooth second-order Gauss-Markov standard deviation "
      "east,north,up, metres (default 0.5,0.5,1)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_per_axis("composite-sigma", v.back(), false, "metres");
        for (std::size_t i = 0; i < 3; ++i) d.receiver.settings.noise.composite.smooth_gm[i].sigma_m = x[i];
      });
  add("composite-tau", "T[,TN,TU]", "composite model: smooth Gauss-Markov correlation time east,north,up, "
      "seconds > 0 (default 20,20,20)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_per_axis("composite-tau", v.back(), true, "seconds");
        for (std::size_t i = 0; i < 3; ++i) d.receiver.settings.noise.composite.smooth_gm[i].tau_s = x[i];
      });
  // The composite model's jitter and jump process: one value for the three axes or one each.
  struct CompositeKey {
    const char* name;
    const char* value_name;
    const char* help;
    const char* unit;
    double noise::CompositeAxis::*field;
  };
  for (const CompositeKey& k : {
           CompositeKey{"composite-jitter", "S[,SN,SU]", "composite model: white jitter standard deviation "
                        "east,north,up, one draw per epoch, metres (default 0,0,0)", "metres",
                        &noise::CompositeAxis::jitter_sigma_m},
           CompositeKey{"composite-jump-rate", "R[,RN,RU]", "composite model: jumps per second east,north,up "
                        "(Poisson) (default 0,0,0)", "per second", &noise::CompositeAxis::jump_rate_hz},
           CompositeKey{"composite-jump-size", "S[,SN,SU]", "composite model: jump size standard deviation "
                        "east,north,up (normal), metres (default 0,0,0)", "metres", &noise::CompositeAxis::jump_sigma_m},
           CompositeKey{"composite-jump-decay", "T[,TN,TU]", "composite model: time constant a jump decays back "
                        "with, east,north,up, seconds; 0 = jumps stay (default 0,0,0)", "seconds",
                        &noise::CompositeAxis::jump_decay_s},
           CompositeKey{"composite-slow-sigma", "S[,SN,SU]", "composite model: slow second-order Gauss-Markov "
                        "wander's standard deviation east,north,up, metres; 0 = none (default 0,0,0)", "metres",
                        &noise::CompositeAxis::slow_sigma_m},
           CompositeKey{"composite-slow-tau", "T[,TN,TU]", "composite model: slow wander's correlation time "
                        "east,north,up, seconds (> 0 where composite-slow-sigma is)", "seconds",
                        &noise::CompositeAxis::slow_tau_s}}) {
    add(k.name, k.value_name, k.help, [k](ConfigDraft& d, V v) {
      const auto x = parse_per_axis(k.name, v.back(), false, k.unit);
      for (std::size_t i = 0; i < 3; ++i) d.receiver.settings.noise.composite.axes[i].*k.field = x[i];
    });
  }
}

}  // namespace gpsemu
