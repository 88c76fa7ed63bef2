// UBX NAV-RELPOSNED (class 0x01 id 0x3C), version 1, 64 bytes (u-blox F9 HPG 1.13): a rover's
// position relative to its base (a moving base on the same vehicle: the baseline and the heading
// it gives). Pure: the relative position's values in, the payload out.
//
// Offsets (checked against ArduPilot's AP_GPS_UBLOX ubx_nav_relposned and PX4-GPSDrivers'
// ubx_payload_rx_nav_relposned_t): 0 version U1 (1), 1 reserved, 2 refStationId U2, 4 iTOW U4,
// 8/12/16 relPosN/E/D I4 (cm), 20 relPosLength I4 (cm), 24 relPosHeading I4 (1e-5 deg), 28
// reserved[4], 32/33/34 relPosHPN/E/D I1 (0.1 mm), 35 relPosHPLength I1, 36/40/44 accN/E/D U4
// (0.1 mm), 48 accLength U4, 52 accHeading U4 (1e-5 deg), 56 reserved[4], 60 flags X4.
#pragma once

#include <cstdint>
#include <string>

#include "emulator/model/epoch.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::ubx {

/// The model's values under their u-blox names (emulator/model/epoch.hpp).
using CarrierSolution = gpsemu::CarrierSolution;
using RelPosNed = gpsemu::RelativePosition;

/// The version-1 payload (64 bytes). gnssFixOK is the fix's; without a fix every relative value
/// is written 0 and only isMoving can be set, as a rover does.
[[nodiscard]] std::string nav_relposned(const nmea::Fix& fix, const RelPosNed& rel);

/// The same fields read back from a version-1 payload (tests, and a check of the layout).
struct RelPosNedFields {
  std::uint8_t version = 0;
  std::uint32_t itow_ms = 0;
  std::int32_t n_cm = 0, e_cm = 0, d_cm = 0, length_cm = 0, heading_1e5deg = 0;
  std::int8_t hp_n = 0, hp_e = 0, hp_d = 0, hp_length = 0;  ///< 0.1 mm
  std::uint32_t acc_n = 0, acc_e = 0, acc_d = 0, acc_length = 0, acc_heading_1e5deg = 0;
  std::uint32_t flags = 0;
};
/// nullopt-free: a payload of another size gives version 0.
[[nodiscard]] RelPosNedFields read_relposned(const std::string& payload);

}  // namespace gpsemu::ubx
