// NAV-RELPOSNED of an RTK rover whose base is a fixed station (docs/rtk.md "NAV-RELPOSNED"): an
// F9P rover fed a base's RTCM3 reports where it is relative to the base's antenna reference point
// (1005/1006). Pure: the RTK state, the base position and the rover's reported fix in, the
// relative position out (model/epoch.hpp; the u-blox encoder writes it as NAV-RELPOSNED).
//
//   relPos N/E/D  rover - base, in the local north/east/down frame at the base (metres)
//   length        |relPos| (3-D)
//   accN/E/D      the fix's 1-sigma north/east/vertical accuracy (its GST sigmas, as NAV-PVT
//                 reports them: what the RTK state made of them, floored once)
//   accLength     the accuracy along the baseline: sqrt(sum (relPos_i / length)^2 acc_i^2)
//   flags         gnssFixOK (the fix's), diffSoln (corrections in use), relPosValid (differential
//                 and the base position known), carrSoln none / float / fixed from the RTK state,
//                 isMoving 0, refPosMiss 0 and refObsMiss 0 (u-blox defines both for a moving
//                 base only: a fixed base's position and observations are not extrapolated),
//                 relPosHeadingValid 0 (a heading belongs to a moving-base baseline)
#pragma once

#include <optional>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/rtk_state.hpp"
#include "emulator/model/epoch.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::rtk {

/// North, east and down metres of `to_ecef_m` from `from` (an ECEF point) in `from`'s local frame.
struct NedOffset {
  double north_m = 0.0, east_m = 0.0, down_m = 0.0;
};
[[nodiscard]] NedOffset ned_from(const BasePosition& from, double to_x_m, double to_y_m, double to_z_m);

/// The values above for a rover whose reported fix is `fix`, at RTK state `status`, with the
/// base position `base` (empty until a 1005/1006 arrived). Without a fix: all zero (the encoder
/// then writes only what a rover without a solution writes).
[[nodiscard]] RelativePosition static_base_relpos(const RtkStatus& status, const std::optional<BasePosition>& base,
                                                const nmea::Fix& fix);

}  // namespace gpsemu::rtk
