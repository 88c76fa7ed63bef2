// The RTK state machine (see rtk_state.hpp).
#include "emulator/rtk/rtk_state.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace gpsemu::rtk {
namespace {

using Q = nmea::FixQuality;

int rank(Q q) {
  switch (q) {
    case Q::rtk_fixed: return 3;
    case Q::rtk_float: return 2;
    case Q::dgps: return 1;
    default: return 0;
  }
}

Q lower(Q a, Q b) { return rank(a) <= rank(b) ? a : b; }

void require(bool ok, std::string_view key, double value, std::string_view range) {
  if (!ok) throw std::invalid_argument(fmt::format("{}: expected {}, got {}", key, range, value));
}

}  // namespace

void validate(const RtkTimeline& t) {
  require(std::isfinite(t.float_after_s) && t.float_after_s >= 0, "seconds to float", t.float_after_s, "seconds >= 0");
  require(std::isfinite(t.fix_base_s) && t.fix_base_s >= t.float_after_s, "seconds to fixed", t.fix_base_s,
          "seconds >= the seconds to float");
  require(std::isfinite(t.fix_per_km_s) && t.fix_per_km_s >= 0, "seconds per km", t.fix_per_km_s, "seconds >= 0");
  require(std::isfinite(t.max_baseline_km) && t.max_baseline_km > 0, "maximum baseline", t.max_baseline_km, "km > 0");
  require(std::isfinite(t.fixed_max_age_s) && t.fixed_max_age_s > 0, "fixed timeout", t.fixed_max_age_s, "seconds > 0");
  require(std::isfinite(t.float_max_age_s) && t.float_max_age_s >= t.fixed_max_age_s, "float timeout",
          t.float_max_age_s, "seconds >= the fixed timeout");
  require(std::isfinite(t.dgps_max_age_s) && t.dgps_max_age_s >= t.float_max_age_s, "DGPS timeout",
          t.dgps_max_age_s, "seconds >= the float timeout");
}

void RtkState::received(const Rtcm3Message& message) {
  if (!message.valid) return;
  if (message.base) base_ = message.base;
  if (message.station_id) station_id_ = message.station_id;
  if (message.msm) msm_pending_ = true;
}

double RtkState::fixed_after_s(double baseline_m) const {
  return timeline_.fix_base_s + timeline_.fix_per_km_s * baseline_m / 1000.0;
}

RtkStatus RtkState::step(double time_s, const std::optional<std::array<double, 3>>& rover_ecef_m) {
  if (msm_pending_) {
    msm_pending_ = false;
    last_msm_s_ = time_s;
    if (!converging_from_s_) converging_from_s_ = time_s;
  }
  RtkStatus s;
  if (base_ && rover_ecef_m) {
    const std::array<double, 3>& r = *rover_ecef_m;
    s.baseline_m = std::hypot(r[0] - base_->ecef_x_m, r[1] - base_->ecef_y_m, r[2] - base_->ecef_z_m);
  }
  if (!last_msm_s_) return s;
  const double age_s = time_s - *last_msm_s_;
  if (age_s > timeline_.dgps_max_age_s) {
    converging_from_s_.reset();
    return s;
  }
  s.correction_age_s = age_s;
  s.station_id = station_id_;
  Q q = Q::dgps;
  if (s.baseline_m && *s.baseline_m <= timeline_.max_baseline_km * 1000.0 && converging_from_s_) {
    const double converged_s = time_s - *converging_from_s_;
    if (converged_s >= fixed_after_s(*s.baseline_m)) {
      q = Q::rtk_fixed;
    } else if (converged_s >= timeline_.float_after_s) {
      q = Q::rtk_float;
    }
  }
  if (age_s > timeline_.float_max_age_s) {
    q = Q::dgps;
    converging_from_s_.reset();  // the ambiguities are lost: converge again from the next MSM
  } else if (age_s > timeline_.fixed_max_age_s) {
    q = lower(q, Q::rtk_float);
  }
  s.quality = lower(q, timeline_.best);
  return s;
}

}  // namespace gpsemu::rtk
