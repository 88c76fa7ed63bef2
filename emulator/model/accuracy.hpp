// The accuracy a receiver reports, as facts of the receiver below every protocol: the floor of
// each fix quality, applied once where the epoch is built (the receiver model, the RTK state, a
// fault that changes the quality); the encoders (UBX hAcc/vAcc/sAcc, GST, NAV-COV) write what the
// epoch says. Pure (its own small library, gpsemu_facts, which the protocol libraries link).
#pragma once

#include "nmea/fix.hpp"

namespace gpsemu::sky {

/// The smallest accuracies a receiver reports with a fix of a quality (1 sigma): no receiver
/// reports 0. Applied once, by the receiver model (and the RTK state); the protocols encode what
/// the epoch says.
struct AccuracyFloor {
  double axis_m = 0.0;      ///< each horizontal axis (metres): gps 0.3, dgps 0.2, rtk_float 0.05, rtk_fixed 0.01
  double vertical_m = 0.0;  ///< vertical (metres): 1.5 x the axis
  double speed_mps = 0.0;   ///< speed (metres per second): 0.05, RTK 0.02
};
[[nodiscard]] AccuracyFloor accuracy_floor(nmea::FixQuality quality);
/// The fix's sigmas (GST: lat, lon, alt, range RMS) raised to its quality's floor: the one place
/// the floor is applied (the model, the RTK state and a fault that changes the quality call it).
void apply_accuracy_floor(nmea::Fix& fix);
/// The horizontal accuracy the fix states (metres, 1 sigma): the root sum of its two axes' sigmas,
/// as u-blox hAcc and the bench view report it.
[[nodiscard]] double horizontal_accuracy_m(const nmea::Fix& fix);
/// accuracy_floor(quality).axis_m.
[[nodiscard]] inline double accuracy_floor_m(nmea::FixQuality quality) { return accuracy_floor(quality).axis_m; }

}  // namespace gpsemu::sky
