// The effects of the faults on the sky, the position's drift and the time (sky-mask, spoof, time):
// plain functions of a fix that fault_timeline.cpp applies at the epochs a fault covers.
// docs/faults.md is the catalogue.
#pragma once

#include <chrono>
#include <optional>
#include <vector>

#include "emulator/faults/fault.hpp"
#include "emulator/model/enu.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/sky.hpp"
#include "emulator/model/sky/dop.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::faults {

/// Whether a satellite at `azimuth_deg`, `elevation_deg` is behind one of `mask`'s sectors.
[[nodiscard]] bool masked(const std::vector<SkyMaskSector>& mask, double azimuth_deg, double elevation_deg);

/// The DOPs of the satellites a fix lists as used (sky::multi_clock_dops, one clock per system).
[[nodiscard]] sky::Dops used_dops(const nmea::Fix& fix);

/// After a fault took satellites out of the solution (their `used` cleared or their entries
/// removed), from the geometry they had (`before`, used_dops() before the change): the DOPs become
/// the geometry of the used ones left (when they were the geometry's before; otherwise, a --hdop
/// or 2-D scale, the ratio applied to the fix's own DOPs, so that scale stays), satellites_used their count, the sigmas grow with HDOP and VDOP times
/// `tracking_k` (a jam's weaker signals), and the position error about `truth_m` (when given) by
/// the HDOP ratio times `tracking_k`. Under kMinFixSatellites used, or a geometry that fixes nothing
/// (4 satellites of two systems: five unknowns): no fix. Returns whether the fix stays.
bool resolve_used_set(nmea::Fix& fix, const sky::Dops& before, double tracking_k, const std::optional<Enu>& truth_m,
                      const LocalFrame& frame);

/// sky-mask: the satellites behind `mask` leave the sky (not in view: GSV, NAV-SAT) and the
/// solution; the DOPs follow the geometry of the used ones left (sky::multi_clock_dops, the ratio
/// applied to the fix's own DOPs), the sigmas and the position error about `truth_m` (when given)
/// grow with HDOP and VDOP; under kMinFixSatellites used, or a geometry that fixes nothing: no fix.
void mask_sky(nmea::Fix& fix, const std::vector<SkyMaskSector>& mask, const std::optional<Enu>& truth_m,
              const LocalFrame& frame);

/// spoof `p` of fault `f`, `since_s` after the first epoch: the position moved by speed_mps x
/// (since_s - at_s) towards bearing_deg plus the offset (ramped in over f.ramp_s), the velocity
/// (speed, course) plus the drag's, the time plus time_drift_ms_per_s x (since_s - at_s): a
/// consistent false trajectory a naive filter follows. Without a fix only the time moves.
/// `ended_s`: the spoof ended then and fades out over f.ramp_out_s: the position and time offsets
/// it had reached shrink linearly to nothing (the velocity carries the return), so the position
/// does not snap back.
void spoof(nmea::Fix& fix, const Fault& f, const Spoof& p, double since_s, const LocalFrame& frame,
           std::optional<double> ended_s = std::nullopt);

/// time: the reported time stepped by jump_s, the date 1024 weeks early (a rollover), or a leap
/// second inserted at the end of p.leap_day (insert_leap_second).
void shift_time(nmea::Fix& fix, const TimeFault& p);

/// A leap second inserted at the end of UTC day `day`, `fix.time_utc` on the receiver's running
/// clock (UTC as counted before it): before the event the change is announced (fix.leap: +1, the
/// seconds to it); from the event's first second the time reads 23:59:60 of `day` (fix.leap.
/// in_second_60), then runs one second behind with GPS - UTC one more; GPS time stays continuous.
void insert_leap_second(nmea::Fix& fix, std::chrono::sys_days day);

/// NAV-STATUS spoofDetState (flags2 bits 3-4) a spoof reports: 3 (multiple spoofing indications)
/// when detected, 1 (no spoofing indicated) when not; 0 (unknown) without a spoof.
[[nodiscard]] inline std::uint8_t spoof_detection_state(bool detected) { return detected ? 3 : 1; }

}  // namespace gpsemu::faults
