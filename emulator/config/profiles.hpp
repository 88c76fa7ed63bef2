// Receiver profiles (data/profiles/, docs/noise-and-calibration.md#receiver-profiles): named configs,
// each calibrated from a real receiver's log by tools/update-profiles and compiled into the program
// by CMake, so an installed gpsemu has them. `--profile NAME` (or `profile = "NAME"` in a config file)
// applies one's keys before the config file's and the command line's, which override them. A profile
// is a config file with a `[profile]` table of what `gpsemu profiles` lists (the loader skips it).
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace gpsemu::profiles {

/// One profile as compiled in: its name (data/profiles/NAME.toml) and the file's text.
struct Profile {
  std::string_view name;
  std::string_view text;
};

/// Every profile, in name order (data/profiles/*.toml but sources.toml; profile_data.cpp.in).
[[nodiscard]] const std::vector<Profile>& catalogue();
/// The profile named `name`, or nullptr.
[[nodiscard]] const Profile* find(std::string_view name);
/// The profile named `name`; throws std::invalid_argument naming every profile when there is none.
[[nodiscard]] const Profile& get(std::string_view name);

/// What `gpsemu profiles` lists of a profile: its `[profile]` table (written by tools/update-profiles).
struct Summary {
  std::string name;
  std::string receiver;                  ///< the receiver as its log names it
  std::string model;                     ///< the --receiver model it sets; empty for none
  std::string log;                       ///< the log it is calibrated from (path in the repository)
  std::string licence, source, recorded, conditions, note;
  double rate_hz = 0.0;                  ///< the log's rate (the profile's --rate)
  std::string noise;                     ///< the noise model calibrate chose
  std::array<double, 3> sigma_m{};       ///< the log's standard deviation east, north, up (metres)
  int satellites = 0;                    ///< median satellites used in the log (0: not in the log)
  double hdop = 0.0;                     ///< median HDOP in the log (0: not in the log)
  double score = 0.0;                    ///< calibrate's score of the chosen model (0 = identical)
  int goal_reached = 0, goal_checks = 0; ///< the 8x run's windows within 25% of the log (sd, d1, d2 per axis)
  std::vector<std::string> goal_misses;  ///< the checks missed, e.g. "north sd -31%"
};

/// The `[profile]` table of `profile`. Throws std::invalid_argument when it is missing or incomplete.
[[nodiscard]] Summary summary(const Profile& profile);

}  // namespace gpsemu::profiles
