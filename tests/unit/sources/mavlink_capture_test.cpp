// A real ArduPilot SITL MAVLink stream (tests/data/mavlink/ardupilot-sitl-quadplane.tlog, with its
// source and licence in the README beside it) through our frame reader: every SIMSTATE checks with
// CRC_EXTRA 154 and every ATTITUDE with 39, every other message is skipped by its length, nothing
// is garbage; the .tlog's
// time stamps between the frames are skipped as garbage and the same SIMSTATEs found; the truth
// decoded lies within a metre and a few degrees of the autopilot's own GLOBAL_POSITION_INT.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "emulator/model/geo.hpp"
#include "emulator/sources/mavlink/mavlink_frame.hpp"
#include "emulator/sources/mavlink/vehicle_state.hpp"

namespace gpsemu::sources::mavlink {
namespace {
namespace mavlink_capture_test {

using Bytes = std::vector<std::uint8_t>;

Bytes read_capture() {
  std::ifstream in(std::string(GPSEMU_SOURCE_DIR) + "/tests/data/mavlink/ardupilot-sitl-quadplane.tlog",
                   std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// One .tlog record: its frame (MAVLink 1 here) and message id.
struct Record {
  Bytes frame;
  std::uint32_t id = 0;
};

std::vector<Record> records_of(const Bytes& tlog) {
  std::vector<Record> out;
  std::size_t at = 0;
  while (at + 8 + kHeaderV1Bytes <= tlog.size()) {
    const std::size_t start = at + 8;  // after the big-endian time stamp
    EXPECT_EQ(tlog[start], kStartV1);
    const std::size_t total = kHeaderV1Bytes + tlog[start + 1] + kCrcBytes;
    out.push_back({Bytes(tlog.begin() + static_cast<std::ptrdiff_t>(start),
                         tlog.begin() + static_cast<std::ptrdiff_t>(start + total)),
                   tlog[start + 5]});
    at = start + total;
  }
  EXPECT_EQ(at, tlog.size());
  return out;
}

std::vector<Frame> read_all(FrameReader& reader, const Bytes& input, std::size_t chunk) {
  std::vector<Frame> out;
  for (std::size_t at = 0; at < input.size(); at += chunk) {
    reader.feed(std::span<const std::uint8_t>(input.data() + at, std::min(chunk, input.size() - at)));
    while (auto f = reader.next()) out.push_back(*f);
  }
  reader.finish();
  while (auto f = reader.next()) out.push_back(*f);
  return out;
}

std::int32_t i4(const Bytes& frame, std::size_t payload_at) {
  const std::size_t p = kHeaderV1Bytes + payload_at;
  return static_cast<std::int32_t>(frame[p] | (frame[p + 1] << 8) | (frame[p + 2] << 16) |
                                   (static_cast<std::uint32_t>(frame[p + 3]) << 24));
}

TEST(MavlinkCapture, EverySimstateOfArduPilotSitlChecksAndTheOtherMessagesAreSkipped) {
  const std::vector<Record> records = records_of(read_capture());
  ASSERT_EQ(records.size(), 986u);
  Bytes frames_only;
  std::size_t simstates = 0, attitudes = 0;
  for (const Record& r : records) {
    frames_only.insert(frames_only.end(), r.frame.begin(), r.frame.end());
    if (r.id == kSimstateId) ++simstates;
    if (r.id == kAttitudeId) ++attitudes;
  }
  EXPECT_EQ(simstates, 36u);
  EXPECT_EQ(attitudes, 36u);
  FrameReader reader;
  const auto frames = read_all(reader, frames_only, 4096);
  EXPECT_EQ(frames.size(), simstates + attitudes);
  EXPECT_EQ(reader.counts().bad_crc, 0u);
  EXPECT_EQ(reader.counts().bad_length, 0u);
  EXPECT_EQ(reader.counts().garbage_bytes, 0u);
  EXPECT_EQ(reader.counts().unknown_message, records.size() - simstates - attitudes);
  for (std::size_t i = 0; i < frames.size(); ++i) {  // ArduPilot's EXTRA1 stream: ATTITUDE, then SIMSTATE
    EXPECT_EQ(frames[i].version, 1);
    EXPECT_EQ(frames[i].system_id, 1);
    EXPECT_EQ(frames[i].message_id, i % 2 == 0 ? kAttitudeId : kSimstateId) << i;
  }
}

TEST(MavlinkCapture, TheTlogTimeStampsBetweenFramesAreSkippedAsGarbage) {
  const Bytes tlog = read_capture();
  for (const std::size_t chunk : {1u, 61u, 1500u}) {
    FrameReader reader;
    const auto frames = read_all(reader, tlog, chunk);
    EXPECT_EQ(frames.size(), 72u) << "chunks of " << chunk;  // 36 ATTITUDE, 36 SIMSTATE
    EXPECT_EQ(reader.counts().bad_crc, 0u);
  }
}

TEST(MavlinkCapture, TheTruthLiesNearTheAutopilotsOwnEstimate) {
  const std::vector<Record> records = records_of(read_capture());
  const LocalFrame frame(Geodetic{-35.363, 149.165, 584.0});
  std::optional<Enu> estimate;
  std::optional<double> estimate_heading_deg;
  std::optional<Enu> first, last;
  double worst_m = 0.0, worst_heading_deg = 0.0;
  int compared = 0;
  for (const Record& r : records) {
    if (r.id == 33) {  // GLOBAL_POSITION_INT: time_boot_ms, lat, lon (degE7), alt, relative_alt, vx, vy, vz, hdg (cdeg)
      estimate = frame.to_enu({i4(r.frame, 4) * 1e-7, i4(r.frame, 8) * 1e-7, 584.0});
      estimate_heading_deg = (r.frame[kHeaderV1Bytes + 26] | (r.frame[kHeaderV1Bytes + 27] << 8)) / 100.0;
      continue;
    }
    if (r.id != kSimstateId) continue;
    FrameReader reader;
    reader.feed(r.frame);
    const auto f = reader.next();
    ASSERT_TRUE(f);
    const auto state = std::get<VehicleState>(decode_state(*f));
    EXPECT_FALSE(state.alt_msl_m);
    EXPECT_FALSE(state.velocity);
    const Enu truth = frame.to_enu({state.lat_deg, state.lon_deg, 584.0});
    if (!first) first = truth;
    last = truth;
    if (!estimate) continue;
    worst_m = std::max(worst_m, std::hypot(truth.east_m - estimate->east_m, truth.north_m - estimate->north_m));
    worst_heading_deg =
        std::max(worst_heading_deg, std::abs(std::remainder(state.yaw_deg - *estimate_heading_deg, 360.0)));
    ++compared;
  }
  EXPECT_EQ(compared, 36);
  EXPECT_LT(worst_m, 1.0) << "SIMSTATE against GLOBAL_POSITION_INT (m)";
  EXPECT_LT(worst_heading_deg, 5.0) << "SIMSTATE yaw against GLOBAL_POSITION_INT hdg (degrees)";
  ASSERT_TRUE(first && last);
  EXPECT_GT(std::hypot(last->east_m - first->east_m, last->north_m - first->north_m), 10.0)
      << "the plane moves (16 m in these 8 s)";
  std::printf("[ info ] ArduPilot SITL capture: %d SIMSTATE, worst %.2f m and %.1f deg from the autopilot's estimate, "
              "%.0f m from the first to the last\n", compared, worst_m, worst_heading_deg,
              std::hypot(last->east_m - first->east_m, last->north_m - first->north_m));
}

}  // namespace mavlink_capture_test
}  // namespace
}  // namespace gpsemu::sources::mavlink
