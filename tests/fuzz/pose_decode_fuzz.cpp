// libFuzzer target for the udp:/tcp: pose input's pure parts: decode_pose() on the whole input
// (as one datagram) and on each '\n'-separated piece (as TCP lines), then the accepted poses
// through a small PoseHistory with arrival times taken from the input, sampled around each pose.
// Checks: nothing crashes, an accepted pose is finite and in range, decoding is deterministic,
// and every sampled truth is finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "emulator/sources/pose_history.hpp"
#include "emulator/sources/pose_message.hpp"

namespace {

using namespace gpsemu;
using namespace gpsemu::sources;

void check(bool ok) {
  if (!ok) std::abort();
}

bool finite(const Enu& e) { return std::isfinite(e.east_m) && std::isfinite(e.north_m) && std::isfinite(e.up_m); }

/// Decodes; on success checks the pose and returns it in local metres (geodetic: a crude stand-in,
/// the history only needs finite numbers).
std::optional<TimedPose> decode_checked(std::string_view bytes, UtcNs arrival) {
  const PoseDecodeResult r = decode_pose(bytes);
  const PoseDecodeResult again = decode_pose(bytes);
  check(r.index() == again.index());
  if (const auto* why = std::get_if<PoseReject>(&r)) {
    check(static_cast<std::size_t>(*why) < kPoseRejectCount);
    check(*why == std::get<PoseReject>(again));
    return std::nullopt;
  }
  const auto& m = std::get<PoseMessage>(r);
  check(bytes.size() <= kMaxPoseMessageBytes);
  if (m.sender_time_s) check(std::isfinite(*m.sender_time_s));
  Enu position;
  if (const auto* g = std::get_if<GeodeticPose>(&m.position)) {
    check(std::abs(g->lat_deg) <= 90.0 && std::abs(g->lon_deg) <= 180.0);
    if (g->alt_msl_m) check(*g->alt_msl_m >= kMinAltM && *g->alt_msl_m <= kMaxAltM);
    position = {g->lon_deg * 1000.0, g->lat_deg * 1000.0, g->alt_msl_m.value_or(0.0)};
  } else {
    position = std::get<Enu>(m.position);
    check(finite(position) && std::abs(position.east_m) <= kMaxLocalCoordinateM &&
          std::abs(position.north_m) <= kMaxLocalCoordinateM && std::abs(position.up_m) <= kMaxLocalCoordinateM);
  }
  if (m.velocity_mps) check(finite(*m.velocity_mps));
  return TimedPose{arrival, m.sender_time_s, position, m.velocity_mps, m.yaw_deg, Tilt{m.pitch_deg, m.roll_deg}};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  (void)decode_checked(input, UtcNs{});

  PoseHistoryOptions options;
  options.capacity = 8;
  PoseHistory history(options);
  UtcNs arrival{std::chrono::seconds(1'700'000'000)};
  std::size_t start = 0;
  while (start <= input.size()) {
    const std::size_t nl = std::min(input.find('\n', start), input.size());
    const std::string_view line = input.substr(start, nl - start);
    // Arrival spacing from the line's first byte: 0..255 ms, so floods, gaps and timeouts all occur.
    const int step_ms = line.empty() ? 20 : static_cast<unsigned char>(line[0]);
    arrival += std::chrono::milliseconds(step_ms) * (line.size() % 7 == 0 ? 5 : 1);
    if (auto pose = decode_checked(line, arrival)) (void)history.push(*pose);
    for (const auto dt : {-30, 0, 7, 150, 400, 1200}) {
      if (const auto truth = history.sample(arrival + std::chrono::milliseconds(dt))) {
        check(finite(truth->position_m) && finite(truth->velocity_mps));
      }
    }
    start = nl + 1;
  }
  return 0;
}
