#include "emulator/faults/sky_faults.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "emulator/faults/fault_timeline.hpp"
#include "emulator/model/sky/dop.hpp"

namespace gpsemu::faults {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

double ratio(double after, double before) { return before > 0.0 ? after / before : 1.0; }

}  // namespace

sky::Dops used_dops(const nmea::Fix& fix) {
  std::vector<sky::UsedSatellite> used;
  for (int i = 0; i < fix.satellites_in_view; ++i) {
    const nmea::SatelliteInView& s = fix.satellites[static_cast<std::size_t>(i)];
    if (s.used) used.push_back({double(s.azimuth_deg), double(s.elevation_deg), s.system});
  }
  return sky::multi_clock_dops(used);
}

bool resolve_used_set(nmea::Fix& fix, const sky::Dops& before, double tracking_k, const std::optional<Enu>& truth_m,
                      const LocalFrame& frame) {
  if (!fix.has_fix()) return false;
  int used = 0;
  for (int i = 0; i < fix.satellites_in_view; ++i) used += fix.satellites[static_cast<std::size_t>(i)].used;
  const sky::Dops after = used_dops(fix);
  if (used < kMinFixSatellites || !after.valid()) {
    drop_fix(fix);
    return false;
  }
  fix.satellites_used = used;
  const double kh = ratio(after.hdop, before.hdop), kv = ratio(after.vdop, before.vdop);
  // DOPs that were the listed geometry's (within the rounding of the listed azimuths and
  // elevations) become the new geometry's; others (--hdop, a 2-D fix's) keep their scale.
  const auto near = [](double a, double b) { return std::abs(a - b) <= 0.02 * b; };
  if (near(fix.hdop, before.hdop) && near(fix.vdop, before.vdop)) {
    fix.hdop = after.hdop;
    fix.vdop = after.vdop;
    fix.pdop = after.pdop;
    fix.tdop = after.tdop;
    fix.gdop = after.gdop;
  } else {
    fix.hdop *= kh;
    fix.vdop *= kv;
    fix.pdop *= ratio(after.pdop, before.pdop);
    fix.tdop *= ratio(after.tdop, before.tdop);
    fix.gdop *= ratio(after.gdop, before.gdop);
  }
  fix.sigma_lat_m *= kh * tracking_k;
  fix.sigma_lon_m *= kh * tracking_k;
  fix.sigma_alt_m *= kv * tracking_k;
  fix.range_rms_m *= tracking_k;
  if (truth_m) scale_error(fix, *truth_m, kh * tracking_k, frame);
  return true;
}

bool masked(const std::vector<SkyMaskSector>& mask, double azimuth_deg, double elevation_deg) {
  for (const SkyMaskSector& s : mask) {
    const bool inside = s.from_azimuth_deg <= s.to_azimuth_deg
                            ? (azimuth_deg >= s.from_azimuth_deg && azimuth_deg < s.to_azimuth_deg)
                            : (azimuth_deg >= s.from_azimuth_deg || azimuth_deg < s.to_azimuth_deg);
    if (inside && elevation_deg < s.min_elevation_deg) return true;
  }
  return false;
}

void mask_sky(nmea::Fix& fix, const std::vector<SkyMaskSector>& mask, const std::optional<Enu>& truth_m,
              const LocalFrame& frame) {
  const sky::Dops before = used_dops(fix);
  int kept = 0;
  for (int i = 0; i < fix.satellites_in_view; ++i) {
    const nmea::SatelliteInView s = fix.satellites[static_cast<std::size_t>(i)];
    if (masked(mask, s.azimuth_deg, s.elevation_deg)) continue;
    fix.satellites[static_cast<std::size_t>(kept++)] = s;
  }
  for (int i = kept; i < fix.satellites_in_view; ++i) fix.satellites[static_cast<std::size_t>(i)] = {};
  fix.satellites_in_view = kept;
  (void)resolve_used_set(fix, before, 1.0, truth_m, frame);
}

void spoof(nmea::Fix& fix, const Fault& f, const Spoof& p, double since_s, const LocalFrame& frame,
           std::optional<double> ended_s) {
  // Fading out: the offsets reached at the end, times k falling from 1 to 0 over ramp_out_s.
  const double until_s = ended_s ? std::min(since_s, *ended_s) : since_s;
  const double k = ended_s && f.ramp_out_s > 0.0 ? std::clamp(1.0 - (since_s - *ended_s) / f.ramp_out_s, 0.0, 1.0) : 1.0;
  const double elapsed_s = std::max(0.0, until_s - f.at_s);
  fix.time_utc += std::chrono::milliseconds(std::llround(k * p.time_drift_ms_per_s * elapsed_s));
  if (!fix.has_fix()) return;
  const double bearing = p.bearing_deg * kDegToRad;
  const Enu drag_mps{p.speed_mps * std::sin(bearing), p.speed_mps * std::cos(bearing), 0.0};
  const Enu reached_m = elapsed_s * drag_mps + f.strength_at(until_s) * p.offset_m;
  offset_position(fix, k * reached_m, frame);
  // The velocity of the false trajectory: the drag while on, the return (-reached / ramp_out_s) while fading.
  const Enu moving_mps = !ended_s ? drag_mps : k > 0.0 ? (-1.0 / f.ramp_out_s) * reached_m : Enu{};
  const double course = fix.course_deg_true.value_or(0.0) * kDegToRad;
  const double east_mps = fix.speed_mps * std::sin(course) + moving_mps.east_m;
  const double north_mps = fix.speed_mps * std::cos(course) + moving_mps.north_m;
  fix.speed_mps = std::hypot(east_mps, north_mps);
  if (fix.speed_mps > 0.05) {
    double deg = std::atan2(east_mps, north_mps) / kDegToRad;
    if (deg < 0.0) deg += 360.0;
    fix.course_deg_true = deg;
  }
}

void insert_leap_second(nmea::Fix& fix, std::chrono::sys_days day) {
  using namespace std::chrono;
  // The receiver's clock runs on (GPS time); UTC as it counted before the leap second reaches the
  // event (the end of `day`) at its midnight: from there UTC counts 23:59:60 once, then one
  // second behind, with one leap second more.
  const nmea::UtcTime event{day + days{1}};
  const nmea::UtcTime t = fix.time_utc;
  fix.leap.event_day = day;
  if (t < event) {
    fix.leap.change_s = 1;
    fix.leap.time_to_event_s = ceil<seconds>(event - t).count();
    return;
  }
  fix.leap.change_s = 0;
  fix.leap.time_to_event_s = -floor<seconds>(t - event).count();
  fix.leap.gps_minus_utc_s += 1;
  fix.leap.in_second_60 = t < event + seconds{1};
  fix.time_utc -= seconds{1};
}

void shift_time(nmea::Fix& fix, const TimeFault& p) {
  if (p.mode == TimeFaultMode::leap_second) {
    insert_leap_second(fix, p.leap_day);
  } else if (p.mode == TimeFaultMode::rollover) {
    fix.time_utc -= std::chrono::weeks(kRolloverWeeks);
  } else {
    fix.time_utc += std::chrono::milliseconds(std::llround(p.jump_s * 1000.0));
  }
}

}  // namespace gpsemu::faults
