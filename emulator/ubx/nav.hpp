// UBX navigation messages (class NAV) from one epoch's fix: the payloads a u-blox writes each
// epoch, NAV-PVT first. Byte layouts follow u-blox's interface descriptions (M8 protocol 18+,
// F9 27+); offsets checked against gpsd's driver_ubx.c, PX4-GPSDrivers ubx.h and ArduPilot's
// AP_GPS_UBLOX.h. Pure: a fix and a few receiver values in, payload bytes out.
//
// Where the fix is silent: accuracies come from its GST sigmas (hAcc = hypot(sigma_lat,
// sigma_lon), vAcc = sigma_alt) and NavExtras::speed_sigma_mps; the vertical velocity is 0; time
// is UTC + gps_leap_seconds; TDOP = 0.6 PDOP (GDOP = hypot(PDOP, TDOP)), NDOP = EDOP = HDOP/sqrt 2.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "emulator/ubx/frame.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::ubx {

/// GPS time minus UTC since 2017-01-01 (seconds); u-blox's default until a new leap second.
inline constexpr int gps_leap_seconds = 18;

/// GPS week and time of week of a UTC time.
struct GpsTime {
  int week = 0;               ///< weeks since 1980-01-06
  std::uint32_t tow_ms = 0;   ///< milliseconds into the week (NAV messages' iTOW)
};
[[nodiscard]] GpsTime gps_time(nmea::UtcTime utc);

/// Receiver values the NAV messages carry beside the fix.
struct NavExtras {
  double speed_sigma_mps = 0.0;                  ///< 1-sigma speed error (sAcc), metres per second
  std::chrono::milliseconds since_start{0};      ///< since the receiver started (NAV-STATUS msss)
  std::chrono::milliseconds time_to_first_fix{0};  ///< NAV-STATUS ttff; 0 before the first fix
};

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
[[nodiscard]] std::string nav_timeutc(const nmea::Fix& fix);
/// NAV-TIMEGPS, 16 bytes.
[[nodiscard]] std::string nav_timegps(const nmea::Fix& fix);
/// NAV-SAT, 8 + 12 per satellite in view (the GSV satellites; GPS PRNs 1-32, SBAS 33-64,
/// GLONASS 65-96 mapped to u-blox gnssId/svId).
[[nodiscard]] std::string nav_sat(const nmea::Fix& fix);
/// NAV-COV, 64 bytes (NED covariances from the sigmas; off-diagonal terms 0).
[[nodiscard]] std::string nav_cov(const nmea::Fix& fix, const NavExtras& extras);
/// NAV-EOE, 4 bytes (the epoch's iTOW): the end-of-epoch marker (protocol 18+), written after
/// every other NAV message and the NMEA sentences of the epoch.
[[nodiscard]] std::string nav_eoe(const nmea::Fix& fix);

/// Whether `id` is one of the NAV messages above.
[[nodiscard]] bool nav_encodes(MessageId id);
/// The payload of NAV message `id` (one of the above), or nullopt for a message not encoded.
[[nodiscard]] std::optional<std::string> nav_payload(MessageId id, const nmea::Fix& fix, const NavExtras& extras);

}  // namespace gpsemu::ubx
