// `gpsemu profiles [NAME]`: the receiver profiles compiled in (config/profiles.hpp). Without NAME a
// table of every profile (receiver, log, rate, noise model, the log's sigma, satellites and HDOP,
// calibrate's score and the 8x run's fidelity goal) and the goal's misses; with NAME the config the
// profile stands for, as it is compiled in (`gpsemu profiles NAME > my.toml`, then --config my.toml).
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "emulator/app/subcommands.hpp"
#include "emulator/config/profiles.hpp"

namespace gpsemu {
namespace {

std::string profile_table() {
  std::string out = fmt::format("{:<18} {:<10} {:<42} {:>5} {:<14} {:>20} {:>5} {:>5} {:>6} {}\n", "PROFILE", "--receiver",
                                "LOG", "HZ", "NOISE", "SIGMA E/N/U (m)", "SATS", "HDOP", "SCORE", "GOAL (8x run)");
  std::string misses;
  for (const profiles::Profile& p : profiles::catalogue()) {
    const profiles::Summary s = profiles::summary(p);
    const auto log = s.log.substr(s.log.rfind('/') + 1);
    out += fmt::format("{:<18} {:<10} {:<42} {:>5g} {:<14} {:>20} {:>5} {:>5} {:>6.3f} {} of {}\n", s.name,
                       s.model.empty() ? "generic" : s.model, log, s.rate_hz, s.noise,
                       fmt::format("{:.3g}/{:.3g}/{:.3g}", s.sigma_m[0], s.sigma_m[1], s.sigma_m[2]),
                       s.satellites > 0 ? std::to_string(s.satellites) : "-",
                       s.hdop > 0.0 ? fmt::format("{:.2f}", s.hdop) : "-", s.score, s.goal_reached, s.goal_checks);
    if (!s.goal_misses.empty()) {
      std::string list;
      for (const std::string& m : s.goal_misses) list += (list.empty() ? "" : ", ") + m;
      misses += fmt::format("  {}: {}\n", s.name, list);
    }
  }
  out += "\nreceiver: as its log names it; SIGMA: the log's standard deviation; SCORE: calibrate's (0 = the log's "
         "statistics exactly);\nGOAL: of sd, d1 sd and d2 sd east and north, the median of 8 windows of an 8x run "
         "within 25% of the log's.\n";
  if (!misses.empty()) out += "goal missed:\n" + misses;
  out += "`gpsemu profiles NAME` prints one's config, its log's source, licence and conditions; --profile NAME uses it.\n";
  return out;
}

}  // namespace

Subcommand add_profiles_command(CLI::App& app) {
  auto name = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand(
      "profiles", "list the receiver profiles (--profile NAME: real receivers calibrated from their logs), or print "
                  "the config one stands for");
  sub->add_option("name", *name, "a profile: print its config (with its log's source, licence and conditions)")
      ->option_text("NAME");
  return {sub, [name](const Config&, const std::atomic<bool>&) {
            if (name->empty()) {
              std::fputs(profile_table().c_str(), stdout);
            } else {
              const profiles::Profile& p = profiles::get(*name);  // throws naming every profile: exit 2
              std::fwrite(p.text.data(), 1, p.text.size(), stdout);
            }
            return 0;
          }};
}

}  // namespace gpsemu
