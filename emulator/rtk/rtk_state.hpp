// The RTK state machine of a u-blox ZED-F9P rover (docs/rtk.md, "The state timeline"): what the
// corrections it receives make of its fix. Pure: the RTCM3 messages that arrived and the time of
// each epoch in, the solution state out; the receiver channel applies it to the fix (the fix
// quality's noise scale, GGA quality 4/5, correction age and station id, NAV-PVT carrSoln).
//
//   no corrections           -> the fix as configured (3-D)
//   observations (MSM) of a base whose position (1005/1006) is known, baseline <= max_baseline_km:
//     from the first          -> DGPS
//     after float_after_s     -> RTK float
//     after fixed_after_s     -> RTK fixed   (fixed_after_s = fix_base_s + fix_per_km_s x baseline_km)
//   a base beyond max_baseline_km, or MSM without a base position: DGPS only
//   corrections stop (age = time since the last MSM):
//     age > fixed_max_age_s   -> RTK float
//     age > float_max_age_s   -> DGPS
//     age > dgps_max_age_s    -> the fix as configured (the F9P's DGNSS timeout, 60 s by default)
// A DGNSS-only receiver (RtkTimeline::best dgps, an M9N) stays at DGPS while corrections come.
// Once the state has fallen to DGPS or below, convergence starts again (float, then fixed, counted
// from the first MSM after the gap); a float reached by age alone returns to fixed at the next MSM.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::rtk {

/// The timeline's parameters (docs/rtk.md; --rtk-convergence, --rtk-timeouts, --rtk-max-baseline).
/// All durations in seconds.
struct RtkTimeline {
  double float_after_s = 3.0;     ///< from the first MSM to RTK float, >= 0
  double fix_base_s = 10.0;       ///< from the first MSM to RTK fixed at a zero baseline, >= float_after_s
  double fix_per_km_s = 2.0;      ///< added to the time to fix per km of baseline, >= 0
  double max_baseline_km = 50.0;  ///< beyond it, DGPS only, > 0
  double fixed_max_age_s = 5.0;   ///< correction age up to which a fixed solution holds
  double float_max_age_s = 30.0;  ///< correction age up to which a float solution holds
  double dgps_max_age_s = 60.0;   ///< correction age up to which the fix stays differential
  /// The best state the receiver reaches: rtk_fixed (an F9P's HPG firmware), dgps (an M9N: its
  /// SPG firmware uses RTCM3 for DGNSS only). From --receiver, not an option.
  nmea::FixQuality best = nmea::FixQuality::rtk_fixed;
};

/// The state at one epoch.
struct RtkStatus {
  nmea::FixQuality quality = nmea::FixQuality::gps;  ///< gps (no corrections), dgps, rtk_float, rtk_fixed
  std::optional<double> correction_age_s;            ///< since the last MSM; empty without corrections
  std::optional<std::uint16_t> station_id;           ///< the base's (1005/1006 or MSM DF003)
  std::optional<double> baseline_m;                  ///< rover to base antenna, when the base position is known
  [[nodiscard]] bool differential() const { return quality != nmea::FixQuality::gps; }
};

class RtkState {
 public:
  explicit RtkState(RtkTimeline timeline = {}) : timeline_(timeline) {}

  /// A decoded message arrived (any source: the u-blox port, --rtcm). Invalid ones are ignored.
  void received(const Rtcm3Message& message);
  /// The state at `time_s` (seconds on any monotonic scale, non-decreasing between calls) for a
  /// rover at `rover_ecef_m` (x, y, z; empty: no position yet). Messages received since the last
  /// call count as arrived at `time_s`.
  [[nodiscard]] RtkStatus step(double time_s, const std::optional<std::array<double, 3>>& rover_ecef_m);
  /// Forgets everything (a cold start).
  void reset() { *this = RtkState(timeline_); }

  /// The time from the first MSM to RTK fixed for a baseline of `baseline_m`.
  [[nodiscard]] double fixed_after_s(double baseline_m) const;
  [[nodiscard]] const RtkTimeline& timeline() const { return timeline_; }
  [[nodiscard]] const std::optional<BasePosition>& base() const { return base_; }

 private:
  RtkTimeline timeline_;
  std::optional<BasePosition> base_;
  std::optional<std::uint16_t> station_id_;
  bool msm_pending_ = false;              // an MSM arrived since the last step
  std::optional<double> last_msm_s_;      // time of the last MSM
  std::optional<double> converging_from_s_;  // first MSM of the current streak
};

/// Validates `t` (at start-up); throws std::invalid_argument naming the field ("seconds to fixed")
/// and its range; the caller prefixes the option's name.
void validate(const RtkTimeline& t);

}  // namespace gpsemu::rtk
