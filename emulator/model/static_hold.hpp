// Static hold (static navigation): what SiRF, SkyTraq and u-blox receivers do when they think they
// stand still. While the speed (3-D: a climb in place is motion) is below a threshold the receiver
// repeats its last reported position, and lets it go when its own (noisy) position wanders farther
// than a radius from it, or when it moves faster. SiRF and SkyTraq logs repeat the previous position in 57% and
// 94% of epochs (issue 27); calibration fits the radius from a log's share of repeated positions
// (emulator/calibration/hold_fit.hpp). Pure and deterministic.
#pragma once

#include <cmath>
#include <optional>

#include "emulator/model/enu.hpp"

namespace gpsemu {

struct StaticHoldOptions {
  /// Horizontal distance (metres) the receiver's own position may wander from the held one before
  /// a new position is reported; 0 = no hold.
  double radius_m = 0.0;
  /// The position is held only while the speed (3-D, the receiver model passes it) is below this (metres/second).
  double max_speed_mps = 0.3;
  [[nodiscard]] bool enabled() const { return radius_m > 0.0; }
};

class StaticHold {
 public:
  explicit StaticHold(const StaticHoldOptions& options = {}) : options_(options) {}

  /// The position to report for the receiver's own position `position_m` (local ENU metres) at
  /// `speed_mps`: the held one while the hold lasts, else `position_m` (which is then held).
  [[nodiscard]] Enu apply(const Enu& position_m, double speed_mps) {
    holding_ = false;
    if (!options_.enabled()) return position_m;
    if (held_ && speed_mps < options_.max_speed_mps &&
        std::hypot(position_m.east_m - held_->east_m, position_m.north_m - held_->north_m) <= options_.radius_m) {
      holding_ = true;
      return *held_;
    }
    held_ = position_m;
    return position_m;
  }

  /// Whether the last apply() returned the held position (a receiver holding also reports no motion).
  [[nodiscard]] bool holding() const { return holding_; }

  /// Forgets the held position (no fix, a restart): the next position is reported as it is.
  void reset() {
    held_.reset();
    holding_ = false;
  }

  [[nodiscard]] const StaticHoldOptions& options() const { return options_; }

 private:
  StaticHoldOptions options_;
  std::optional<Enu> held_;
  bool holding_ = false;
};

}  // namespace gpsemu
