// UBX navigation messages (class NAV) from one epoch's fix: the payloads a u-blox writes each
// epoch, NAV-PVT first. Byte layouts follow u-blox's interface descriptions (M8 protocol 18+,
// F9 27+); offsets checked against gpsd's driver_ubx.c, PX4-GPSDrivers ubx.h and ArduPilot's
// AP_GPS_UBLOX.h. Pure: a fix and a few receiver values in, payload bytes out.
//
// Where the fix is silent: accuracies come from its GST sigmas (hAcc = hypot(sigma_lat,
// sigma_lon), vAcc = sigma_alt, sAcc = sigma_speed_mps, floored once by the model:
// sky::accuracy_floor); velD is -vel_up_mps; time is UTC +
// gps_leap_seconds, its validity flags NavExtras::time's; TDOP and GDOP the fix's, or when it has
// none (0) TDOP = 0.6 PDOP and GDOP = hypot(PDOP, TDOP); NDOP = EDOP = HDOP/sqrt 2.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "emulator/ubx/frame.hpp"
#include "emulator/ubx/model.hpp"
#include "emulator/ubx/nav_sat.hpp"
#include "emulator/model/epoch.hpp"
#include "emulator/ubx/relposned.hpp"
#include "emulator/ubx/relposned.hpp"
#include "emulator/model/gps_time.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::ubx {

/// GPS time minus UTC since 2017-01-01 (seconds); u-blox's default until a new leap second.
inline constexpr int gps_leap_seconds = kGpsMinusUtcDefaultS;

/// GPS week and time of week (iTOW): the model's (emulator/model/gps_time.hpp).
using gpsemu::ClockState;
using gpsemu::GpsTime;
using gpsemu::RfState;
using gpsemu::TimeValidity;
using gpsemu::gps_time;

/// Receiver values the NAV messages carry beside the fix.
struct NavExtras {
  std::chrono::milliseconds since_start{0};      ///< since the receiver started (NAV-STATUS msss)
  std::chrono::milliseconds time_to_first_fix{0};  ///< NAV-STATUS ttff; 0 before the first fix
  ReceiverModel model = ReceiverModel::generic;  ///< what NAV-SIG lists (bands) and MON-RF's blocks
  TimeValidity time{};                           ///< how much of the time the receiver knows
  ClockState clock{};                            ///< NAV-CLOCK
  RfState rf{};                                  ///< MON-HW, MON-RF
  RelPosNed relpos{};                            ///< NAV-RELPOSNED (a rover's; zeros elsewhere)
};

/// The fix's 1-sigma position accuracy as the NAV messages report it (metres): its GST sigmas as
/// they are (the model floored them once: sky::accuracy_floor): NAV-PVT hAcc = hypot(north, east),
/// vAcc = down; NAV-RELPOSNED's accN/accE/accD are these.
struct NedAccuracy {
  double north_m = 0.0, east_m = 0.0, down_m = 0.0;
};
[[nodiscard]] NedAccuracy position_accuracy(const nmea::Fix& fix);

/// hAcc/vAcc/sAcc a u-blox reports without a fix (mm, mm, mm/s).
inline constexpr std::uint32_t no_fix_accuracy_mm = 0xFFFFFFFF;
inline constexpr std::uint32_t no_fix_speed_accuracy_mm_s = 20000;

/// NAV-PVT, 92 bytes.
[[nodiscard]] std::string nav_pvt(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-POSLLH, 28 bytes.
[[nodiscard]] std::string nav_posllh(const nmea::Fix& fix);
/// NAV-VELNED, 36 bytes.
[[nodiscard]] std::string nav_velned(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-STATUS, 16 bytes.
[[nodiscard]] std::string nav_status(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-SOL, 52 bytes (ECEF position and velocity; older M8 drivers read it).
[[nodiscard]] std::string nav_sol(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-POSECEF, 20 bytes (NAV-SOL's ECEF position and pAcc; gpsd turns it on).
[[nodiscard]] std::string nav_posecef(const nmea::Fix& fix);
/// NAV-VELECEF, 20 bytes (NAV-SOL's ECEF velocity and sAcc; gpsd turns it on).
[[nodiscard]] std::string nav_velecef(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-DOP, 18 bytes.
[[nodiscard]] std::string nav_dop(const nmea::Fix& fix);
/// NAV-TIMEUTC, 20 bytes.
[[nodiscard]] std::string nav_timeutc(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-TIMEGPS, 16 bytes.
[[nodiscard]] std::string nav_timegps(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-TIMELS, 24 bytes (nav_time.cpp): the current leap seconds (the fix's, from GPS) once UTC
/// is resolved; a change the fix announces (fix.leap: lsChange, timeToLsEvent, its GPS week and
/// day), else none and the last event (end of 2016-12-31, GPS week 1929 day 7).
[[nodiscard]] std::string nav_timels(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-CLOCK, 20 bytes (NavExtras::clock).
[[nodiscard]] std::string nav_clock(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-HPPOSLLH, 36 bytes (F9): NAV-POSLLH's position with the 1e-9 degree and 0.1 mm parts.
[[nodiscard]] std::string nav_hpposllh(const nmea::Fix& fix);
/// NAV-COV, 64 bytes (NED covariances from the sigmas; off-diagonal terms 0).
[[nodiscard]] std::string nav_cov(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-EOE, 4 bytes (the epoch's iTOW): the end-of-epoch marker (protocol 18+), written after
/// every other NAV message and the NMEA sentences of the epoch.
[[nodiscard]] std::string nav_eoe(const nmea::Fix& fix);

}  // namespace gpsemu::ubx
