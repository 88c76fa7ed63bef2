// Test support for the fault unit tests: the 3-D gps fix at a place that each of them builds its
// satellites and DOPs on, and the check that a fault's keys are refused with the reason.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>

#include "emulator/faults/fault.hpp"
#include "emulator/faults/fault_timeline.hpp"
#include "emulator/model/epoch.hpp"
#include "emulator/model/enu.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/time.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::test {

/// A 3-D gps fix at `position_m` (in `frame`) at `t` (to the millisecond); no satellites yet.
inline nmea::Fix gps_fix_at(const LocalFrame& frame, UtcNs t, const Enu& position_m) {
  nmea::Fix fix;
  fix.time_utc = std::chrono::floor<std::chrono::milliseconds>(t);
  fix.quality = nmea::FixQuality::gps;
  fix.dimension = nmea::FixDimension::three_d;
  const Geodetic g = frame.to_geodetic(position_m);
  fix.lat_deg = g.lat_deg;
  fix.lon_deg = g.lon_deg;
  fix.alt_msl_m = g.alt_m;
  return fix;
}

/// One epoch through `timeline` as the channel applies it: `fix` in a fresh epoch (a clean RF
/// front end), the faults applied, the fix handed back and, when asked, the epoch's front end.
inline faults::EpochEffect apply_faults(faults::FaultTimeline& timeline, UtcNs t, nmea::Fix& fix,
                                        const std::optional<Enu>& truth_m, const LocalFrame& frame,
                                        RfState* rf = nullptr) {
  ReceiverEpoch epoch;
  epoch.fix = fix;
  const faults::EpochEffect effect = timeline.apply(t, epoch, truth_m, frame);
  fix = epoch.fix;
  if (rf) *rf = epoch.rf;
  return effect;
}

/// make_fault(keys) throws std::invalid_argument whose message holds `part`.
inline void expect_fault_refused(const faults::FaultKeys& keys, const std::string& part) {
  try {
    (void)faults::make_fault(keys);
    ADD_FAILURE() << "accepted: " << part;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

}  // namespace gpsemu::test
