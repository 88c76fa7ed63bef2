// libFuzzer target for the mavlink: pose input's pure parts: the frame reader over the whole input
// as one datagram and as a TCP stream cut into reads (sizes from the input), the states decoded
// from its frames, and those states through a small PoseHistory. Checks: nothing crashes, both
// cuts find the same frames (a stream is not cut differently by its reads), the counters add up,
// decoding is deterministic, every accepted state is finite and in range, every sampled truth finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "emulator/model/geo.hpp"
#include "emulator/sources/mavlink/mavlink_frame.hpp"
#include "emulator/sources/mavlink/vehicle_state.hpp"
#include "emulator/sources/pose_history.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using namespace gpsemu;
using namespace gpsemu::sources;
using namespace gpsemu::sources::mavlink;

bool finite(const Enu& e) { return std::isfinite(e.east_m) && std::isfinite(e.north_m) && std::isfinite(e.up_m); }

std::vector<Frame> read(std::span<const std::uint8_t> input, std::size_t chunk, FrameCounts& counts) {
  FrameReader reader;
  std::vector<Frame> frames;
  for (std::size_t at = 0; at < input.size(); at += chunk) {
    reader.feed(input.subspan(at, std::min(chunk, input.size() - at)));
    while (auto f = reader.next()) frames.push_back(*f);
  }
  reader.finish();
  while (auto f = reader.next()) frames.push_back(*f);
  counts = reader.counts();
  return frames;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> input(data, size);
  FrameCounts whole_counts, cut_counts;
  const std::vector<Frame> whole = read(input, size == 0 ? 1 : size, whole_counts);
  const std::size_t chunk = size == 0 ? 1 : 1 + data[0] % 61;
  const std::vector<Frame> cut = read(input, chunk, cut_counts);
  GPSEMU_FUZZ_CHECK(whole.size() == cut.size());
  GPSEMU_FUZZ_CHECK(whole_counts.frames == whole.size());
  GPSEMU_FUZZ_CHECK(whole_counts.garbage_bytes == cut_counts.garbage_bytes);
  GPSEMU_FUZZ_CHECK(whole_counts.unknown_message == cut_counts.unknown_message);

  const LocalFrame frame(Geodetic{43.0725, -89.4125, 260.0});
  PoseHistoryOptions options;
  options.capacity = 8;
  PoseHistory history(options);
  UtcNs arrival{std::chrono::seconds(1'700'000'000)};
  for (std::size_t i = 0; i < whole.size(); ++i) {
    const Frame& f = whole[i];
    GPSEMU_FUZZ_CHECK(f.message_id == cut[i].message_id && f.sequence == cut[i].sequence);
    const MessageInfo* info = find_message(f.message_id);
    GPSEMU_FUZZ_CHECK(info != nullptr && f.wire_length <= info->full_length);
    const StateDecodeResult r = decode_state(f);
    GPSEMU_FUZZ_CHECK(r.index() == decode_state(f).index());
    arrival += std::chrono::milliseconds(f.sequence);
    if (const auto* s = std::get_if<VehicleState>(&r)) {
      GPSEMU_FUZZ_CHECK(std::abs(s->lat_deg) <= 90.0 && std::abs(s->lon_deg) <= 180.0);
      GPSEMU_FUZZ_CHECK(s->yaw_deg >= 0.0 && s->yaw_deg < 360.0 && std::abs(s->pitch_deg) <= 90.0 + 1e-6);
      if (s->alt_msl_m) GPSEMU_FUZZ_CHECK(*s->alt_msl_m >= kMinAltM && *s->alt_msl_m <= kMaxAltM);
      const Enu p = frame.to_enu({s->lat_deg, s->lon_deg, s->alt_msl_m.value_or(260.0)});
      std::optional<Enu> v;
      if (s->velocity) v = Enu{s->velocity->east_mps, s->velocity->north_mps, -s->velocity->down_mps};
      GPSEMU_FUZZ_CHECK(finite(p) && (!v || finite(*v)));
      (void)history.push(TimedPose{arrival, std::nullopt, p, v, s->yaw_deg, Tilt{s->pitch_deg, s->roll_deg}});
    }
    for (const int dt : {-30, 0, 150, 1200}) {
      if (const auto truth = history.sample(arrival + std::chrono::milliseconds(dt))) {
        GPSEMU_FUZZ_CHECK(finite(truth->position_m) && finite(truth->velocity_mps));
      }
    }
  }
  return 0;
}
