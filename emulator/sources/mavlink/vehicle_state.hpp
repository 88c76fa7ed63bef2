// The vehicle's true state in the three MAVLink messages a simulator sends (pure): SIM_STATE
// (id 108, ArduPilot SITL), HIL_STATE_QUATERNION (115, PX4's ground truth) and SIMSTATE
// (164, ArduPilot), decoded from a checked frame (mavlink_frame.hpp) into one value with units in
// its names, and encoded back (frames for tests, the fuzz corpus and tools).
//
// Payloads are little-endian, fields in wire order (by type size, largest first; extension fields
// last), as message_definitions/v1.0/common.xml and ardupilotmega.xml define them:
//   SIM_STATE             q1..q4, roll, pitch, yaw (rad), xacc..zacc, xgyro..zgyro, lat, lon (deg,
//                         float), alt (m), std_dev_horz, std_dev_vert, vn, ve, vd (m/s): 21 floats;
//                         extensions lat_int, lon_int (degE7; 0: use the floats; ArduPilot's
//                         SITL writes degE7 into the floats too: beyond ±90/±180 they are read so)
//   HIL_STATE_QUATERNION  time_usec (u64), attitude_quaternion[4], rollspeed..yawspeed (floats),
//                         lat, lon (degE7), alt (mm) (i32), vx, vy, vz (cm/s, N/E/D) (i16),
//                         ind_airspeed, true_airspeed (u16), xacc..zacc (i16)
//   SIMSTATE              roll, pitch, yaw (rad), xacc..zacc, xgyro..zgyro (floats), lat, lng (degE7)
//                         (no altitude, no velocity)
// Attitude: SIM_STATE's quaternion when it is a unit one (else its Euler angles), HIL_STATE_
// QUATERNION's quaternion, SIMSTATE's Euler angles; yaw clockwise from north, pitch nose up,
// roll right side down (NED body angles, the same convention as a JSON pose's yaw/pitch/roll).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "emulator/sources/mavlink/mavlink_frame.hpp"
#include "emulator/sources/pose_message.hpp"

namespace gpsemu::sources::mavlink {

/// Velocity in the local North/East/Down frame (metres per second).
struct VelocityNed {
  double north_mps = 0.0;
  double east_mps = 0.0;
  double down_mps = 0.0;
};

/// One message's truth.
struct VehicleState {
  std::uint32_t message_id = 0;
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  std::optional<double> alt_msl_m;          ///< SIMSTATE carries none
  std::optional<VelocityNed> velocity;      ///< SIMSTATE carries none
  double roll_deg = 0.0;                    ///< right side down positive, -180..180
  double pitch_deg = 0.0;                   ///< nose up positive, -90..90
  double yaw_deg = 0.0;                     ///< clockwise from north, [0, 360)
  std::optional<std::uint64_t> time_usec;   ///< HIL_STATE_QUATERNION's time stamp, when not 0
};

/// Why a checked frame's values were not used (counted by the source like JSON poses' reasons).
using StateDecodeResult = std::variant<VehicleState, PoseReject>;

/// Decodes a frame of one of kMessages: not_finite (NaN, infinity), out_of_range (latitude,
/// longitude, altitude, speed as for JSON poses), missing_key (latitude and longitude both 0:
/// a simulator without a position yet).
[[nodiscard]] StateDecodeResult decode_state(const Frame& frame);

/// An ATTITUDE frame's time_boot_ms (milliseconds since the autopilot booted), or nothing for another frame.
[[nodiscard]] std::optional<std::uint32_t> attitude_time_boot_ms(const Frame& frame);

/// Euler angles (degrees; yaw in [0, 360)) of a unit quaternion w, x, y, z (NED body to earth).
struct Euler {
  double roll_deg = 0.0;
  double pitch_deg = 0.0;
  double yaw_deg = 0.0;
};
[[nodiscard]] Euler euler_of_quaternion(double w, double x, double y, double z);
/// The unit quaternion w, x, y, z of Euler angles (degrees).
[[nodiscard]] std::array<double, 4> quaternion_of_euler(const Euler& angles);

/// How encode_frame() writes a frame.
struct EncodeOptions {
  int version = 2;                 ///< 1 or 2
  std::uint8_t sequence = 0;
  std::uint8_t system_id = 1;
  std::uint8_t component_id = 1;
  bool truncate = true;            ///< MAVLink 2: cut trailing zero bytes (at least one byte stays)
  bool sign = false;               ///< MAVLink 2: set the signed flag and append a 13-byte signature (zeros)
};

/// A frame of `id` (one of kMessages) carrying `payload` (its full length; MAVLink 1 sends the base
/// fields only).
[[nodiscard]] std::vector<std::uint8_t> encode_frame(std::uint32_t id, std::span<const std::uint8_t> payload,
                                                     const EncodeOptions& options = {});
/// A frame of any message `id` whose CRC_EXTRA is given (one gpsemu writes but does not read,
/// stream_request.hpp); the payload is written as given (MAVLink 2: trailing zeros cut).
[[nodiscard]] std::vector<std::uint8_t> encode_frame(std::uint32_t id, std::uint8_t crc_extra,
                                                     std::span<const std::uint8_t> payload,
                                                     const EncodeOptions& options = {});
/// A frame of `message_id` carrying `state` (alt 0 and zero velocity when not given; time_usec 0).
[[nodiscard]] std::vector<std::uint8_t> encode_state(const VehicleState& state, const EncodeOptions& options = {});

}  // namespace gpsemu::sources::mavlink
