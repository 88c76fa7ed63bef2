// libFuzzer target for the mavlink: source's per-sender handling (sources/mavlink_source.hpp) as the
// loop drives it: a scripted pose socket hands MavlinkPoseSource what the input says, one event a
// service() call. Byte 0 chooses UDP datagrams or a TCP stream; then records of
//   byte 0: sender (low 3 bits, 8 UDP senders or TCP connections), MAVLink system id (bits 3-4:
//           1..4), kind (bits 5-6: a state frame made here, raw bytes, a disconnection, ATTITUDE);
//   byte 1: time since the previous record (10 ms units, 0..2.55 s, around the 1 s timeout);
//   a state: byte 2 the message (SIM_STATE, HIL_STATE_QUATERNION, SIMSTATE) and MAVLink 1 or 2,
//           byte 3 a position offset; raw: byte 2 the length, then the bytes (junk, cut frames).
// Every (sender, system) has a track of its own 100 m east of the others' (a state 0..10 m from
// its track), so a truth that mixes two vehicles' states is seen. Checks, after each event:
// - counts: every state frame the source's reader returns is accepted, superseded or dropped
//   (by a reason), exactly once, against a reference reader per datagram or per connection;
// - one vehicle: while a state that owner sent was taken within the timeout, another vehicle's
//   state is never taken; when a state is taken the truth at its arrival is that vehicle's track
//   (never another's, never between two);
// - every truth finite.
// TCP: a connection is one sender (a new sender follows a disconnection, as a reconnect does).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "emulator/model/geo.hpp"
#include "emulator/sources/mavlink/mavlink_frame.hpp"
#include "emulator/sources/mavlink/vehicle_state.hpp"
#include "emulator/sources/mavlink_source.hpp"
#include "tests/fuzz/fuzz_check.hpp"
#include "tests/support/scripted_pose_socket.hpp"

namespace {

using namespace gpsemu;
using namespace gpsemu::sources;
using Kind = transport::ReceivedMessage::Kind;

constexpr double kTrackSpacingM = 100.0;
const LocalFrame kFrame(Geodetic{43.0725, -89.4125, 260.0});

/// The track of (sender, system 1..4): east of the origin by its number (sender * 4 + system - 1) × 100 m.
double track_east_m(std::uint64_t sender, std::uint8_t system) {
  return kTrackSpacingM * static_cast<double>(sender * 4 + (system - 1u));
}

std::uint64_t sum(const MavlinkSourceStats& s) {
  std::uint64_t n = s.accepted + s.superseded;
  for (const std::uint64_t r : s.rejected) n += r;
  return n;
}

/// The state frames (not ATTITUDE) a reader finds: per datagram, or over a connection's bytes.
class ReferenceReader {
 public:
  std::vector<mavlink::Frame> feed(const std::string& bytes) {
    reader_.feed(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
    return take();
  }
  std::vector<mavlink::Frame> finish() {
    reader_.finish();
    return take();
  }

 private:
  std::vector<mavlink::Frame> take() {
    std::vector<mavlink::Frame> frames;
    while (const auto f = reader_.next()) {
      if (f->message_id != mavlink::kAttitudeId) frames.push_back(*f);
    }
    return frames;
  }
  mavlink::FrameReader reader_;
};

bool same(const mavlink::Frame& a, const mavlink::Frame& b) {
  return a.version == b.version && a.sequence == b.sequence && a.system_id == b.system_id &&
         a.message_id == b.message_id && a.wire_length == b.wire_length && a.payload == b.payload;
}

std::string state_frame(std::uint64_t sender, std::uint8_t system, std::uint8_t choice, std::uint8_t offset, std::uint8_t seq) {
  static constexpr std::uint32_t kIds[] = {mavlink::kSimStateId, mavlink::kHilStateQuaternionId, mavlink::kSimstateId};
  mavlink::VehicleState s;
  s.message_id = kIds[choice % 3];
  const Geodetic g = kFrame.to_geodetic(Enu{track_east_m(sender, system) + offset / 25.5, 0.0, 0.0});
  s.lat_deg = g.lat_deg;
  s.lon_deg = g.lon_deg;
  if (s.message_id != mavlink::kSimstateId) {
    s.alt_msl_m = 260.0;
    s.velocity = mavlink::VelocityNed{};
  }
  const auto bytes = mavlink::encode_state(s, {.version = (choice & 0x10) != 0 ? 1 : 2, .sequence = seq, .system_id = system});
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

std::string attitude_frame(std::uint8_t system, std::uint32_t boot_ms) {
  std::uint8_t payload[28] = {};
  for (int i = 0; i < 4; ++i) payload[i] = static_cast<std::uint8_t>(boot_ms >> (8 * i));
  const auto bytes = mavlink::encode_frame(mavlink::kAttitudeId, payload, {.system_id = system});
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool quiet = [] {
    spdlog::set_level(spdlog::level::off);
    return true;
  }();
  (void)quiet;
  if (size == 0) return 0;
  const bool datagrams = (data[0] & 1) != 0;
  std::deque<test::Scripted> queue;
  const MavlinkSourceOptions options{.history = {}, .datagrams = datagrams};
  MavlinkPoseSource source(std::make_unique<test::FakeSocket>(&queue), kFrame, options);

  UtcNs now{std::chrono::seconds(1'700'000'000)};
  ReferenceReader stream;             // TCP: the connection's bytes
  std::optional<std::uint64_t> connection;  // TCP: the sender connected
  std::uint64_t frames_expected = 0;
  // The vehicle whose state was taken last, and when.
  std::optional<std::uint64_t> owner;  // sender * 4 + system - 1
  UtcNs owner_last{};
  bool owner_unknown = false;  // a frame found in raw bytes was taken: whose is not known here
  std::uint8_t seq = 0;

  std::size_t at = 1;
  while (at + 2 <= size) {
    const std::uint8_t head = data[at];
    now += std::chrono::milliseconds(10 * data[at + 1]);
    at += 2;
    std::uint64_t sender = head & 0x07;
    const auto system = static_cast<std::uint8_t>(1 + ((head >> 3) & 0x03));
    const int kind = (head >> 5) & 0x03;
    if (!datagrams && kind != 2 && connection && *connection != sender) sender = *connection;  // one connection at a time
    test::Scripted event{Kind::message, "", now, sender, "sim-" + std::to_string(sender)};
    bool is_state = false;
    if (kind == 0) {
      if (at + 2 > size) break;
      event.bytes = state_frame(sender, system, data[at], data[at + 1], seq++);
      at += 2;
      is_state = true;
    } else if (kind == 1) {
      if (at >= size) break;
      const std::size_t n = std::min<std::size_t>(data[at], size - at - 1);
      event.bytes.assign(reinterpret_cast<const char*>(data) + at + 1, n);
      at += 1 + n;
    } else if (kind == 2) {
      if (datagrams) continue;  // UDP has no connection to lose
      event.kind = Kind::disconnected;
    } else {
      event.bytes = attitude_frame(system, static_cast<std::uint32_t>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                               now.time_since_epoch()).count()));
    }
    // What the source should find in it.
    std::vector<mavlink::Frame> found;
    if (event.kind == Kind::disconnected) {
      found = stream.finish();
      stream = ReferenceReader{};
      if (owner && *owner / 4 == sender) owner.reset();
      connection.reset();
    } else if (datagrams) {
      ReferenceReader one;
      found = one.feed(event.bytes);
      for (const auto& f : one.finish()) found.push_back(f);
    } else {
      connection = sender;
      found = stream.feed(event.bytes);
    }
    frames_expected += found.size();
    // This event's state is the one frame read (not a frame that an earlier cut frame held back).
    bool alone = false;
    if (is_state && found.size() == 1) {
      ReferenceReader ours;
      const std::vector<mavlink::Frame> mine = ours.feed(event.bytes);
      alone = mine.size() == 1 && same(mine[0], found[0]);
    }

    const MavlinkSourceStats before = source.stats();
    queue.push_back(event);
    source.service();
    GPSEMU_FUZZ_CHECK(queue.empty());
    const MavlinkSourceStats& after = source.stats();
    GPSEMU_FUZZ_CHECK(sum(after) == frames_expected);

    const std::uint64_t vehicle = sender * 4 + (system - 1u);
    const std::uint64_t taken = after.accepted - before.accepted;
    if (alone && taken == 1) {
      GPSEMU_FUZZ_CHECK(owner_unknown || !owner || *owner == vehicle || now - owner_last > options.history.timeout);
      owner = vehicle;
      owner_unknown = false;
      owner_last = now;
      const auto truth = source.truth_at(now);
      GPSEMU_FUZZ_CHECK(truth.has_value());
      const double from_track_m = truth->position_m.east_m - track_east_m(sender, system);
      GPSEMU_FUZZ_CHECK(from_track_m > -0.5 && from_track_m < 10.5 && std::abs(truth->position_m.north_m) < 0.5);
    } else if (alone && after.rejected[static_cast<std::size_t>(PoseReject::other_sender)] >
                            before.rejected[static_cast<std::size_t>(PoseReject::other_sender)]) {
      GPSEMU_FUZZ_CHECK(owner_unknown || (owner && *owner != vehicle));
    } else if (taken > 0) {
      owner_unknown = true;
    }
    for (const int dt_ms : {-40, 0, 150, 1100}) {
      if (const auto truth = source.truth_at(now + std::chrono::milliseconds(dt_ms))) {
        GPSEMU_FUZZ_CHECK(std::isfinite(truth->position_m.east_m) && std::isfinite(truth->position_m.north_m) &&
                          std::isfinite(truth->position_m.up_m) && std::isfinite(truth->velocity_mps.east_m));
      }
    }
  }
  return 0;
}
