// What gpsemu writes to a MAVLink peer it connected to (`mavlink:tcp:HOST:PORT`, an autopilot
// SITL's ground-station port): a HEARTBEAT as a ground station, then MAV_CMD_SET_MESSAGE_INTERVAL
// (COMMAND_LONG) for SIM_STATE and for HIL_STATE_QUATERNION. ArduPilot 4.x sends SIM_STATE in no
// default stream (only SIMSTATE, which has no altitude or velocity) and PX4 sends its ground truth
// only when asked, so without the request a copter would fly at the origin's altitude. An
// autopilot that lacks one of the two messages refuses that command and keeps the other. Pure:
// bytes out, no I/O.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

namespace gpsemu::sources::mavlink {

inline constexpr std::uint32_t kHeartbeatId = 0;      ///< HEARTBEAT (common)
inline constexpr std::uint8_t kHeartbeatCrcExtra = 50;
inline constexpr std::uint32_t kCommandLongId = 76;   ///< COMMAND_LONG (common)
inline constexpr std::uint8_t kCommandLongCrcExtra = 152;
inline constexpr std::uint16_t kCmdSetMessageInterval = 511;  ///< MAV_CMD_SET_MESSAGE_INTERVAL
inline constexpr std::uint8_t kGcsSystemId = 255;     ///< the system id gpsemu sends as (a ground station's)
inline constexpr std::uint8_t kGcsComponentId = 190;  ///< MAV_COMP_ID_MISSIONPLANNER

/// The HEARTBEAT and the two COMMAND_LONGs (MAVLink 2 frames, sequence numbers from `sequence`,
/// target system and component 0: every autopilot on the link) asking for SIM_STATE and
/// HIL_STATE_QUATERNION every `interval`.
[[nodiscard]] std::vector<std::uint8_t> stream_request(std::chrono::microseconds interval, std::uint8_t sequence = 0);

}  // namespace gpsemu::sources::mavlink
