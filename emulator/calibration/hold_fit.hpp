// Static hold (emulator/model/static_hold.hpp) fitted from a stationary receiver's log: the share of
// epochs that repeat the previous position exactly (SiRF and SkyTraq static navigation: 57% and
// 94%), against the share the calibrated noise model gives by the log's resolution alone; when the
// log repeats more, the hold radius whose simulation (the best model, the log's rate, gaps and
// resolution) repeats as often. Also the altitude's decimals, which calibrate writes as
// alt-decimals. Written as config keys and shown by calibrate and compare.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "emulator/calibration/receiver_log.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/static_hold.hpp"

namespace gpsemu::calibration {

/// The share of repeated positions above which a hold is fitted: this much more than the model
/// repeats by the resolution alone.
inline constexpr double kHoldMinExcessShare = 0.05;
/// The hold speed written: a stationary log cannot tell the receiver's threshold (it never moves),
/// so a walking pace's fraction that a stationary receiver's own speed noise stays below.
inline constexpr double kCalibratedHoldSpeed_mps = 0.3;

struct HoldFit {
  double real_share = 0.0;     ///< epochs whose east and north equal the previous epoch's (of pairs)
  double model_share = 0.0;    ///< the best model's, without hold (the resolution's repeats alone)
  double held_share = 0.0;     ///< the best model's with the fitted hold (= model_share when none)
  StaticHoldOptions hold{0.0, kCalibratedHoldSpeed_mps};  ///< radius 0: no hold
  bool radius_at_bound = false;  ///< the search's largest radius did not repeat as often as the log
  int alt_decimals = 1;        ///< the log's altitude decimals (written at most 4)
};

/// The share of epochs (with a fix before them) whose east and north equal the previous epoch's.
[[nodiscard]] double repeat_share(const std::array<std::vector<double>, 3>& x);

/// Fits the hold of `series` for the noise model `best` (simulated `runs` times from `seed`).
[[nodiscard]] HoldFit fit_hold(const EnuSeries& series, const noise::NoiseConfig& best, std::uint64_t seed, int runs);

/// The config keys alt-decimals, hold-radius and hold-speed (the hold's only when fitted), with a comment.
[[nodiscard]] std::string hold_toml(const HoldFit& fit);

/// One line for a person: the repeated shares and the fitted hold.
[[nodiscard]] std::string hold_summary(const HoldFit& fit);

}  // namespace gpsemu::calibration
