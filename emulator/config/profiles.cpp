#include "emulator/config/profiles.hpp"

#include <stdexcept>

#include <fmt/format.h>
#include <toml++/toml.h>

namespace gpsemu::profiles {

const Profile* find(std::string_view name) {
  for (const Profile& p : catalogue()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

const Profile& get(std::string_view name) {
  if (const Profile* p = find(name)) return *p;
  std::string names;
  for (const Profile& p : catalogue()) names += (names.empty() ? "" : ", ") + std::string(p.name);
  throw std::invalid_argument(fmt::format("unknown profile '{}' (the profiles: {}; `gpsemu profiles` lists them)",
                                          name, names));
}

Summary summary(const Profile& profile) {
  const toml::table file = toml::parse(profile.text, std::string(profile.name));
  const toml::table* t = file["profile"].as_table();
  if (!t) throw std::invalid_argument(fmt::format("profile {}: no [profile] table", profile.name));
  const auto text = [&](const char* key) {
    const auto v = (*t)[key].value<std::string>();
    if (!v) throw std::invalid_argument(fmt::format("profile {}: [profile] has no '{}'", profile.name, key));
    return *v;
  };
  const auto number = [&](const char* key) {
    const auto v = (*t)[key].value<double>();
    if (!v) throw std::invalid_argument(fmt::format("profile {}: [profile] has no number '{}'", profile.name, key));
    return *v;
  };
  Summary s;
  s.name = text("name");
  s.receiver = text("receiver");
  s.model = text("model");
  s.log = text("log");
  s.licence = text("licence");
  s.source = text("source");
  s.recorded = text("recorded");
  s.conditions = text("conditions");
  s.note = text("note");
  s.rate_hz = number("rate-hz");
  s.noise = text("noise");
  const toml::array* sigma = (*t)["sigma-m"].as_array();
  if (!sigma || sigma->size() != 3) throw std::invalid_argument(fmt::format("profile {}: [profile] sigma-m is not 3 numbers", profile.name));
  for (std::size_t a = 0; a < 3; ++a) s.sigma_m[a] = (*sigma)[a].value<double>().value_or(0.0);
  s.satellites = static_cast<int>(number("satellites"));
  s.hdop = number("hdop");
  s.score = number("score");
  s.goal_reached = static_cast<int>(number("goal-reached"));
  s.goal_checks = static_cast<int>(number("goal-checks"));
  if (const toml::array* misses = (*t)["goal-misses"].as_array()) {
    for (const auto& m : *misses) s.goal_misses.push_back(m.value<std::string>().value_or(""));
  }
  return s;
}

}  // namespace gpsemu::profiles
