// What a receiver knows at one epoch, as one value: built forward once per epoch (the receiver
// model's fix, then RTK and the moving-base rover's relative position, then the faults, which may
// take satellites away, jam the front end or spoof it) and handed read-only to every protocol
// (NMEA, UBX and the next ones). No stage after the faults writes into it, and no protocol is asked
// for a place to write it (ArduPilot's AP_GPS::GPS_State, the flow reversed, as an emulator needs it).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "nmea/fix.hpp"

namespace gpsemu {

/// The carrier-phase solution (u-blox carrSoln, NAV-PVT and NAV-RELPOSNED): none, float or fixed.
enum class CarrierSolution : std::uint8_t { none = 0, floating = 1, fixed = 2 };

/// A rover's position relative to its base at one solution (a moving base on the same vehicle:
/// the baseline and the heading it gives; a fixed base: where the rover is from it). Metres and
/// degrees; zeros when not valid.
struct RelativePosition {
  std::uint16_t ref_station_id = 0;
  double north_m = 0.0, east_m = 0.0, down_m = 0.0;  ///< base antenna -> rover antenna, NED (metres)
  double length_m = 0.0;                             ///< |relPos| (metres)
  double heading_deg = 0.0;                          ///< heading of the baseline, degrees true [0, 360)
  double acc_north_m = 0.0, acc_east_m = 0.0, acc_down_m = 0.0, acc_length_m = 0.0;  ///< 1 sigma (metres)
  double acc_heading_deg = 0.0;                      ///< 1 sigma (degrees)
  bool diff_soln = false;         ///< corrections (the base's RTCM3) applied
  bool rel_pos_valid = false;     ///< the relative position components are valid
  CarrierSolution carrier = CarrierSolution::none;
  bool is_moving = false;         ///< moving-base mode
  bool ref_pos_miss = false;      ///< the base's position was extrapolated (its 4072.0 missing)
  bool ref_obs_miss = false;      ///< the base's observations were extrapolated (its MSM missing)
  bool heading_valid = false;     ///< the baseline's heading is valid
};

/// The RF front end: a clean steady state unless a fault (a jam, a spoof) acts on it this epoch.
/// The units are u-blox's (MON-HW, MON-RF, NAV-STATUS), the one family that reports them so far.
struct RfState {
  std::uint16_t noise_per_ms = 89;     ///< noise level of the correlators (MON-HW noisePerMS)
  std::uint16_t agc_count = 3140;      ///< automatic gain control, 0..8191 (MON-HW agcCnt)
  std::uint8_t jamming_indicator = 9;  ///< CW jamming indicator, 0 (none) .. 255 (strong)
  std::uint8_t jamming_state = 1;      ///< 0 unknown, 1 ok, 2 warning, 3 critical
  std::uint8_t antenna_status = 2;     ///< 0 init, 1 don't know, 2 ok, 3 short, 4 open
  std::uint8_t antenna_power = 1;      ///< 0 off, 1 on, 2 don't know
  /// Spoofing detection: 0 unknown or off, 1 no spoofing indicated, 2 spoofing indicated,
  /// 3 multiple spoofing indications (a spoof fault sets it).
  std::uint8_t spoof_detection_state = 0;
};

/// The receiver clock at an epoch (u-blox NAV-CLOCK's units).
struct ClockState {
  std::int32_t bias_ns = 0;         ///< receiver clock minus GPS time (ns)
  std::int32_t drift_ns_per_s = 0;  ///< its rate (ns/s)
  std::uint32_t time_accuracy_ns = 20;              ///< 1 sigma of the time (ns)
  std::uint32_t frequency_accuracy_ps_per_s = 500;  ///< 1 sigma of the frequency (ps/s)
};

/// How much of the time a receiver knows.
struct TimeValidity {
  bool valid = true;      ///< time of week and week known (u-blox validDate, validTime, TOW/WKN set)
  bool resolved = true;   ///< UTC fully resolved (fullyResolved, validUTC, leap seconds valid)
  bool confirmed = true;  ///< date and time confirmed (confirmedDate, confirmedTime)
};

/// What a receiver knows about itself beside the fix (model/receiver_clock.hpp keeps it).
struct ReceiverStatus {
  std::chrono::milliseconds since_start{0};        ///< since the receiver started (u-blox msss)
  std::chrono::milliseconds time_to_first_fix{0};  ///< 0 before the first fix
  TimeValidity time;
  ClockState clock;
};

/// One epoch of one receiver (the library's gpsemu::Epoch, emulator/library/gpsemu.hpp, is its public summary).
struct ReceiverEpoch {
  nmea::Fix fix;  ///< the solution, the satellites (used or not) and their DOPs, the accuracy
  RfState rf;     ///< the front end
  ReceiverStatus status;  ///< run time, TTFF, time validity and clock, from the fix after the faults
  /// The relative position a rover reports (a moving-base rover, or a rover of a fixed base once
  /// corrections arrived); empty: none (a protocol that reports it writes its zeros).
  std::optional<RelativePosition> relative_position;
};

/// An epoch of `fix` alone: a clean front end, no relative position (an encoder's tests, a replay).
[[nodiscard]] inline ReceiverEpoch epoch_of(const nmea::Fix& fix) {
  ReceiverEpoch epoch;
  epoch.fix = fix;
  return epoch;
}

}  // namespace gpsemu
