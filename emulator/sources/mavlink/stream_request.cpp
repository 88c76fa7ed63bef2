#include "emulator/sources/mavlink/stream_request.hpp"

#include <bit>
#include <cstring>
#include <span>

#include "emulator/sources/mavlink/mavlink_frame.hpp"
#include "emulator/sources/mavlink/vehicle_state.hpp"

namespace gpsemu::sources::mavlink {
namespace {

void put_float(std::vector<std::uint8_t>& p, float x) {
  const auto u = std::bit_cast<std::uint32_t>(x);
  for (int i = 0; i < 4; ++i) p.push_back(static_cast<std::uint8_t>(u >> (8 * i)));
}

// COMMAND_LONG's wire order: param1..param7 (float), command (uint16), target_system,
// target_component, confirmation (uint8): 33 bytes.
std::vector<std::uint8_t> set_message_interval(std::uint32_t message_id, std::chrono::microseconds interval) {
  std::vector<std::uint8_t> p;
  put_float(p, static_cast<float>(message_id));
  put_float(p, static_cast<float>(interval.count()));
  for (int i = 0; i < 5; ++i) put_float(p, 0.0f);
  p.push_back(static_cast<std::uint8_t>(kCmdSetMessageInterval & 0xFF));
  p.push_back(static_cast<std::uint8_t>(kCmdSetMessageInterval >> 8));
  p.insert(p.end(), {0, 0, 0});
  return p;
}

}  // namespace

std::vector<std::uint8_t> stream_request(std::chrono::microseconds interval, std::uint8_t sequence) {
  EncodeOptions o;
  o.system_id = kGcsSystemId;
  o.component_id = kGcsComponentId;
  // HEARTBEAT's wire order: custom_mode (uint32), type, autopilot, base_mode, system_status,
  // mavlink_version: MAV_TYPE_GCS (6), MAV_AUTOPILOT_INVALID (8), MAV_STATE_ACTIVE (4), version 3.
  const std::vector<std::uint8_t> heartbeat{0, 0, 0, 0, 6, 8, 0, 4, 3};
  o.sequence = sequence;
  std::vector<std::uint8_t> out = encode_frame(kHeartbeatId, kHeartbeatCrcExtra, heartbeat, o);
  for (const std::uint32_t id : {kSimStateId, kHilStateQuaternionId}) {
    o.sequence = static_cast<std::uint8_t>(o.sequence + 1);
    const std::vector<std::uint8_t> f = encode_frame(kCommandLongId, kCommandLongCrcExtra, set_message_interval(id, interval), o);
    out.insert(out.end(), f.begin(), f.end());
  }
  return out;
}

}  // namespace gpsemu::sources::mavlink
