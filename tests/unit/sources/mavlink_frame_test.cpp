// The MAVLink frame reader (emulator/sources/mavlink/mavlink_frame.hpp): the X.25 CRC and the
// CRC_EXTRA of our three messages from their definitions, two reference frames written by hand
// from the spec, six frames of an independent implementation (node-mavlink), MAVLink 1 and 2,
// truncated payloads, garbage between frames, frames split over reads, bad CRCs, unknown ids,
// signed frames and cut frames counted and skipped.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "emulator/sources/mavlink/mavlink_frame.hpp"
#include "emulator/sources/mavlink/vehicle_state.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::sources::mavlink {
namespace {
namespace mavlink_frame_test {

using Bytes = std::vector<std::uint8_t>;

Bytes bytes_of(const std::string& hex) {
  const std::string raw = ubx::test::unhex(hex);
  return Bytes(raw.begin(), raw.end());
}

Bytes operator+(Bytes a, const Bytes& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/// Every frame `input` holds, fed in pieces of `chunk` bytes, then finish().
std::vector<Frame> read_all(FrameReader& reader, const Bytes& input, std::size_t chunk = 1 << 20) {
  std::vector<Frame> out;
  for (std::size_t at = 0; at < input.size(); at += chunk) {
    const std::size_t n = std::min(chunk, input.size() - at);
    reader.feed(std::span<const std::uint8_t>(input.data() + at, n));
    while (auto f = reader.next()) out.push_back(*f);
  }
  reader.finish();
  while (auto f = reader.next()) out.push_back(*f);
  return out;
}

// SIMSTATE (164) as MAVLink 1, seq 7, system 1, component 1: roll 0.5, pitch -0.25, yaw 1.5 rad,
// accelerations and rates 0, lat 431234567, lng -894125000 degE7. Written from the spec by hand
// (struct.pack('<9f2i', ...), CRC-16/MCRF4XX over length..payload, then CRC_EXTRA 154).
const char* kSimstateV1 =
    "fe2c070101a4"
    "0000003f000080be0000c03f000000000000000000000000000000000000000000000000071eb41938bcb4ca"
    "09ed";
// SIM_STATE (108) as MAVLink 2, seq 9: quaternion (cos 45°, 0, 0, sin 45°) = yaw 90°, roll and
// pitch 0, yaw field pi/2, lat 43.0725, lon -89.4125 (floats), alt 300.5 m, vn 1.5, ve -2.0,
// vd 0.25 m/s, lat_int 430725000, lon_int -894125000 (92 bytes, nothing to truncate), CRC_EXTRA 32.
const char* kSimStateV2 =
    "fd5c00000901016c0000"
    "f304353f0000000000000000f304353f0000000000000000db0fc93f000000000000000000000000000000000000"
    "0000000000003d4a2c4233d3b2c20040964300000000000000000000c03f000000c00000803e8857ac1938bcb4ca"
    "81f5";

TEST(MavlinkFrame, CrcIsX25McRf4xxWithItsCatalogueCheckValue) {
  // CRC-16/MCRF4XX of "123456789" is 0x6F91 (the CRC catalogue's check value).
  const std::string check = "123456789";
  EXPECT_EQ(crc_x25(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(check.data()), check.size())),
            0x6F91);
}

/// CRC_EXTRA as mavgen computes it: "NAME " then "type name " of each base field in wire order
/// (an array adds its length as a byte), folded to 8 bits.
std::uint8_t crc_extra_of(const std::string& name, const std::vector<std::pair<std::string, int>>& fields) {
  const auto text = [](std::uint16_t crc, const std::string& s) {
    return crc_x25(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()), crc);
  };
  std::uint16_t crc = text(0xFFFF, name + " ");
  for (const auto& [field, array] : fields) {
    crc = text(crc, field + " ");
    if (array > 1) crc = crc_x25(static_cast<std::uint8_t>(array), crc);
  }
  return static_cast<std::uint8_t>((crc & 0xFF) ^ (crc >> 8));
}

TEST(MavlinkFrame, CrcExtrasMatchTheMessageDefinitions) {
  // Base fields in wire order, from message_definitions/v1.0/common.xml and ardupilotmega.xml.
  std::vector<std::pair<std::string, int>> sim_state;
  for (const char* f : {"q1", "q2", "q3", "q4", "roll", "pitch", "yaw", "xacc", "yacc", "zacc", "xgyro", "ygyro",
                        "zgyro", "lat", "lon", "alt", "std_dev_horz", "std_dev_vert", "vn", "ve", "vd"}) {
    sim_state.push_back({std::string("float ") + f, 1});
  }
  const std::vector<std::pair<std::string, int>> hil{
      {"uint64_t time_usec", 1}, {"float attitude_quaternion", 4}, {"float rollspeed", 1}, {"float pitchspeed", 1},
      {"float yawspeed", 1},     {"int32_t lat", 1},               {"int32_t lon", 1},      {"int32_t alt", 1},
      {"int16_t vx", 1},         {"int16_t vy", 1},                {"int16_t vz", 1},       {"uint16_t ind_airspeed", 1},
      {"uint16_t true_airspeed", 1}, {"int16_t xacc", 1},          {"int16_t yacc", 1},     {"int16_t zacc", 1}};
  std::vector<std::pair<std::string, int>> simstate;
  for (const char* f : {"roll", "pitch", "yaw", "xacc", "yacc", "zacc", "xgyro", "ygyro", "zgyro"}) {
    simstate.push_back({std::string("float ") + f, 1});
  }
  simstate.push_back({"int32_t lat", 1});
  simstate.push_back({"int32_t lng", 1});
  EXPECT_EQ(crc_extra_of("SIM_STATE", sim_state), 32);
  EXPECT_EQ(crc_extra_of("HIL_STATE_QUATERNION", hil), 4);
  EXPECT_EQ(crc_extra_of("SIMSTATE", simstate), 154);
  EXPECT_EQ(crc_extra_of("ATTITUDE", {{"uint32_t time_boot_ms", 1}, {"float roll", 1}, {"float pitch", 1}, {"float yaw", 1},
                                      {"float rollspeed", 1}, {"float pitchspeed", 1}, {"float yawspeed", 1}}),
            39);
  EXPECT_EQ(find_message(kAttitudeId)->crc_extra, 39);
  EXPECT_EQ(find_message(kSimStateId)->crc_extra, 32);
  EXPECT_EQ(find_message(kHilStateQuaternionId)->crc_extra, 4);
  EXPECT_EQ(find_message(kSimstateId)->crc_extra, 154);
}

TEST(MavlinkFrame, ReadsTheHandWrittenMavlink1Simstate) {
  FrameReader reader;
  const auto frames = read_all(reader, bytes_of(kSimstateV1));
  ASSERT_EQ(frames.size(), 1u);
  const Frame& f = frames[0];
  EXPECT_EQ(f.version, 1);
  EXPECT_EQ(f.sequence, 7);
  EXPECT_EQ(f.system_id, 1);
  EXPECT_EQ(f.component_id, 1);
  EXPECT_EQ(f.message_id, kSimstateId);
  EXPECT_EQ(f.wire_length, 44);
  const auto state = std::get<VehicleState>(decode_state(f));
  EXPECT_DOUBLE_EQ(state.lat_deg, 43.1234567);
  EXPECT_DOUBLE_EQ(state.lon_deg, -89.4125);
  EXPECT_NEAR(state.roll_deg, 28.6478897565, 1e-9);
  EXPECT_NEAR(state.pitch_deg, -14.3239448783, 1e-9);
  EXPECT_NEAR(state.yaw_deg, 85.9436692696, 1e-9);
  EXPECT_FALSE(state.alt_msl_m);
  EXPECT_FALSE(state.velocity);
  EXPECT_EQ(reader.counts().frames, 1u);
  EXPECT_EQ(reader.counts().garbage_bytes, 0u);
}

TEST(MavlinkFrame, ReadsTheHandWrittenMavlink2SimState) {
  FrameReader reader;
  const auto frames = read_all(reader, bytes_of(kSimStateV2));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].version, 2);
  EXPECT_EQ(frames[0].sequence, 9);
  const auto state = std::get<VehicleState>(decode_state(frames[0]));
  EXPECT_DOUBLE_EQ(state.lat_deg, 43.0725);  // lat_int, not the float
  EXPECT_DOUBLE_EQ(state.lon_deg, -89.4125);
  EXPECT_DOUBLE_EQ(*state.alt_msl_m, 300.5);
  EXPECT_DOUBLE_EQ(state.velocity->north_mps, 1.5);
  EXPECT_DOUBLE_EQ(state.velocity->east_mps, -2.0);
  EXPECT_DOUBLE_EQ(state.velocity->down_mps, 0.25);
  EXPECT_NEAR(state.yaw_deg, 90.0, 1e-4);
  EXPECT_NEAR(state.roll_deg, 0.0, 1e-9);
  EXPECT_NEAR(state.pitch_deg, 0.0, 1e-9);
}

TEST(MavlinkFrame, OurEncoderWritesTheHandWrittenFramesByteForByte) {
  // The reference frames decoded and encoded again (same sequence, ids) give the same bytes.
  for (const char* hex : {kSimstateV1, kSimStateV2}) {
    FrameReader reader;
    const auto frames = read_all(reader, bytes_of(hex));
    ASSERT_EQ(frames.size(), 1u);
    const Frame& f = frames[0];
    const auto again = encode_frame(f.message_id, std::span<const std::uint8_t>(f.payload.data(), f.wire_length),
                                    {.version = f.version, .sequence = f.sequence});
    EXPECT_EQ(again, bytes_of(hex)) << hex;
  }
}

// Frames of an independent implementation: encoded by node-mavlink 2.3.0 with mavlink-mappings
// 1.0.0 (npm; used as a tool, only its output is kept here), system 1, component 1, sequence 5
// (MAVLink 1) and 6 (MAVLink 2, not truncated, SIM_STATE without its extensions). Values: SIM_STATE
// q = (0.9238795, 0, 0, 0.3826834) (yaw 45°), yaw field 0.7853982, zacc -9.81, lat 47.397742,
// lon 8.545594, alt 488.25, vn 2.5, ve 2.5, vd -0.75; HIL_STATE_QUATERNION time_usec
// 1700000000123456, the same quaternion, lat 473977420, lon 85455940, alt 488250, vx 250, vy 250,
// vz -75, zacc -1000; SIMSTATE roll 0.1, pitch -0.05, yaw 0.7853982, zacc -9.81, lat 473977420,
// lng 85455940.
const char* kIndependentFrames[] = {
    "fe540501016c5e836c3f000000000000000014efc33e0000000000000000db0f493f0000000000000000c3f51cc1000000000000"
    "0000000000004a973d42c1ba08410020f44300000000000000000000204000002040000040bfb0c2",
    "fd5400000601016c00005e836c3f000000000000000014efc33e0000000000000000db0f493f0000000000000000c3f51cc10000"
    "000000000000000000004a973d42c1ba08410020f44300000000000000000000204000002040000040bfc2bc",
    "fe400501017340222018240a06005e836c3f000000000000000014efc33e0000000000000000000000004c52401c44f417053a73"
    "0700fa00fa00b5ff000000000000000018fc727f",
    "fd40000006010173000040222018240a06005e836c3f000000000000000014efc33e0000000000000000000000004c52401c44f4"
    "17053a730700fa00fa00b5ff000000000000000018fc933e",
    "fe2c050101a4cdcccc3dcdcc4cbddb0f493f0000000000000000c3f51cc10000000000000000000000004c52401c44f41705bebd",
    "fd2c0000060101a40000cdcccc3dcdcc4cbddb0f493f0000000000000000c3f51cc10000000000000000000000004c52401c44f417055db9",
};

TEST(MavlinkFrame, ReadsTheFramesOfAnIndependentImplementation) {
  Bytes stream;
  for (const char* hex : kIndependentFrames) stream = stream + bytes_of(hex);
  FrameReader reader;
  const auto frames = read_all(reader, stream);
  ASSERT_EQ(frames.size(), 6u);
  EXPECT_EQ(reader.counts().garbage_bytes, 0u);
  const std::uint32_t ids[] = {kSimStateId, kSimStateId, kHilStateQuaternionId, kHilStateQuaternionId, kSimstateId,
                               kSimstateId};
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].message_id, ids[i]);
    EXPECT_EQ(frames[i].version, i % 2 == 0 ? 1 : 2);
    EXPECT_EQ(frames[i].sequence, i % 2 == 0 ? 5 : 6);
    const auto s = std::get<VehicleState>(decode_state(frames[i]));
    EXPECT_NEAR(s.lat_deg, 47.397742, 2e-6) << i;  // SIM_STATE's floats: about 7 digits
    EXPECT_NEAR(s.lon_deg, 8.545594, 1e-6) << i;
    EXPECT_NEAR(s.yaw_deg, 45.0, 1e-4) << i;
    if (ids[i] == kSimstateId) {
      EXPECT_NEAR(s.roll_deg, 5.729578, 1e-5);
      EXPECT_NEAR(s.pitch_deg, -2.864789, 1e-5);
      continue;
    }
    EXPECT_NEAR(*s.alt_msl_m, 488.25, 1e-6) << i;
    EXPECT_NEAR(s.velocity->north_mps, 2.5, 1e-6) << i;
    EXPECT_NEAR(s.velocity->east_mps, 2.5, 1e-6) << i;
    EXPECT_NEAR(s.velocity->down_mps, -0.75, 1e-6) << i;
    if (ids[i] == kHilStateQuaternionId) {
      EXPECT_EQ(s.time_usec, 1'700'000'000'123'456u);
    }
  }
}

VehicleState moving(std::uint32_t id) {
  VehicleState s;
  s.message_id = id;
  s.lat_deg = -33.8568;
  s.lon_deg = 151.2153;
  s.alt_msl_m = 42.0;
  s.velocity = VelocityNed{3.0, 4.0, -1.0};
  s.yaw_deg = 53.13;
  s.pitch_deg = 5.0;
  s.roll_deg = -10.0;
  return s;
}

TEST(MavlinkFrame, EachMessageRoundTripsAsMavlink1AndMavlink2) {
  for (const auto& info : kMessages) {
    if (info.id == kAttitudeId) continue;  // read for its time only
    for (const int version : {1, 2}) {
      FrameReader reader;
      const auto frames = read_all(reader, encode_state(moving(info.id), {.version = version, .system_id = 3}));
      ASSERT_EQ(frames.size(), 1u) << info.name << " v" << version;
      EXPECT_EQ(frames[0].version, version);
      EXPECT_EQ(frames[0].system_id, 3);
      const auto s = std::get<VehicleState>(decode_state(frames[0]));
      // SIM_STATE over MAVLink 1 has no lat_int/lon_int: its floats hold about 7 digits.
      const double tolerance_deg = info.id == kSimStateId && version == 1 ? 1e-5 : 1e-7;
      EXPECT_NEAR(s.lat_deg, -33.8568, tolerance_deg) << info.name;
      EXPECT_NEAR(s.lon_deg, 151.2153, tolerance_deg) << info.name;
      EXPECT_NEAR(s.yaw_deg, 53.13, 1e-4) << info.name;
      EXPECT_NEAR(s.pitch_deg, 5.0, 1e-4) << info.name;
      EXPECT_NEAR(s.roll_deg, -10.0, 1e-4) << info.name;
      if (info.id == kSimstateId) continue;
      EXPECT_NEAR(*s.alt_msl_m, 42.0, 1e-3) << info.name;
      EXPECT_NEAR(s.velocity->north_mps, 3.0, 1e-6) << info.name;
      EXPECT_NEAR(s.velocity->east_mps, 4.0, 1e-6) << info.name;
      EXPECT_NEAR(s.velocity->down_mps, -1.0, 1e-6) << info.name;
    }
  }
}

TEST(MavlinkFrame, Mavlink2TruncatedTrailingZerosAreZeroExtended) {
  // SIM_STATE without lat_int/lon_int and with vd = 0 (level flight): its last 12 bytes are zeros.
  VehicleState s = moving(kSimStateId);
  s.velocity->down_mps = 0.0;
  const Bytes full = encode_state(s, {.truncate = false});
  Bytes payload(full.begin() + kHeaderV2Bytes, full.end() - kCrcBytes);
  std::fill(payload.begin() + 84, payload.end(), 0);
  const Bytes cut = encode_frame(kSimStateId, payload);
  EXPECT_EQ(cut[1], 80);  // 92 bytes less lat_int, lon_int and vd
  FrameReader reader;
  const auto frames = read_all(reader, cut);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].wire_length, 80);
  const auto decoded = std::get<VehicleState>(decode_state(frames[0]));
  EXPECT_NEAR(decoded.lat_deg, -33.8568, 1e-5);  // the float fields: lat_int is 0
  EXPECT_EQ(decoded.velocity->down_mps, 0.0);
}

TEST(MavlinkFrame, GarbageBetweenFramesIsCountedAndSkipped) {
  const Bytes garbage = bytes_of("00 11 22 33 44 55 66 0d 0a");
  const Bytes a = encode_state(moving(kSimStateId), {.sequence = 1});
  const Bytes b = encode_state(moving(kSimstateId), {.version = 1, .sequence = 2});
  FrameReader reader;
  const auto frames = read_all(reader, garbage + a + garbage + b + garbage);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].sequence, 1);
  EXPECT_EQ(frames[1].sequence, 2);
  EXPECT_EQ(reader.counts().garbage_bytes, 3 * garbage.size());
  EXPECT_EQ(reader.counts().frames, 2u);
}

TEST(MavlinkFrame, FalseStartBytesInGarbageDoNotHideTheFramesAfterThem) {
  // A MAVLink 1 "frame" of an unknown id not followed by a start byte, and a MAVLink 2 header of
  // an unknown id whose length reaches into the real frame: both are garbage, the frames are read.
  const Bytes garbage = bytes_of("fe 00 01 02 03 04 05 06 77 fd 09 00 00 00 00 00 99 99 99 88");
  const Bytes a = encode_state(moving(kSimStateId), {.sequence = 1});
  const Bytes b = encode_state(moving(kSimstateId), {.version = 1, .sequence = 2});
  for (const std::size_t chunk : {1u, 13u, 4096u}) {
    FrameReader reader;
    const auto frames = read_all(reader, garbage + a + garbage + b + garbage, chunk);
    ASSERT_EQ(frames.size(), 2u) << "chunks of " << chunk;
    EXPECT_EQ(frames[0].sequence, 1);
    EXPECT_EQ(frames[1].sequence, 2);
    EXPECT_EQ(reader.counts().unknown_message, 0u);
  }
}

TEST(MavlinkFrame, AFrameSplitOverReadsIsReadWhole) {
  const Bytes stream = encode_state(moving(kSimStateId)) + encode_state(moving(kHilStateQuaternionId)) +
                       encode_state(moving(kSimstateId), {.version = 1});
  for (const std::size_t chunk : {1u, 2u, 7u, 50u, 97u}) {
    FrameReader reader;
    const auto frames = read_all(reader, stream, chunk);
    ASSERT_EQ(frames.size(), 3u) << "chunks of " << chunk;
    EXPECT_EQ(frames[0].message_id, kSimStateId);
    EXPECT_EQ(frames[1].message_id, kHilStateQuaternionId);
    EXPECT_EQ(frames[2].message_id, kSimstateId);
    EXPECT_EQ(reader.counts().garbage_bytes, 0u);
  }
}

TEST(MavlinkFrame, AWrongCrcIsCountedAndTheNextFrameRead) {
  Bytes bad = encode_state(moving(kSimStateId), {.sequence = 1});
  bad[bad.size() - 1] ^= 0x5A;
  Bytes corrupted = encode_state(moving(kHilStateQuaternionId), {.sequence = 2});
  corrupted[20] ^= 0x01;  // a payload bit flipped on the way
  const Bytes good = encode_state(moving(kSimstateId), {.sequence = 3});
  FrameReader reader;
  const auto frames = read_all(reader, bad + corrupted + good);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].sequence, 3);
  EXPECT_EQ(reader.counts().bad_crc, 2u);
}

TEST(MavlinkFrame, UnknownMessageIdsAreSkippedAndCounted) {
  // HEARTBEAT (0) and VFR_HUD (74) as an autopilot streams them: not ours, skipped by length.
  const Bytes heartbeat = encode_frame(0, bytes_of("000000000203510403"));
  const Bytes vfr_hud = encode_frame(74, Bytes(20, 0x7E), {.version = 1});
  const Bytes ours = encode_state(moving(kSimStateId));
  FrameReader reader;
  const auto frames = read_all(reader, heartbeat + ours + vfr_hud + heartbeat);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].message_id, kSimStateId);
  EXPECT_EQ(reader.counts().unknown_message, 3u);
  EXPECT_EQ(reader.counts().garbage_bytes, 0u);
}

TEST(MavlinkFrame, SignedFramesAreSkippedWithTheirSignature) {
  const Bytes signed_frame = encode_state(moving(kSimStateId), {.sequence = 1, .sign = true});
  EXPECT_EQ(signed_frame[2], kIncompatSigned);
  const Bytes after = encode_state(moving(kSimStateId), {.sequence = 2});
  FrameReader reader;
  const auto frames = read_all(reader, signed_frame + after);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].sequence, 2);
  EXPECT_EQ(reader.counts().signed_frame, 1u);
  EXPECT_EQ(reader.counts().garbage_bytes, 0u);
}

TEST(MavlinkFrame, UnknownIncompatFlagsAreRefused) {
  Bytes odd = encode_state(moving(kSimStateId), {.sequence = 1});
  odd[2] = 0x02;
  FrameReader reader;
  const auto frames = read_all(reader, odd + encode_state(moving(kSimStateId), {.sequence = 2}));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].sequence, 2);
  EXPECT_EQ(reader.counts().unsupported_flags, 1u);
}

TEST(MavlinkFrame, AFrameCutByTheEndOfInputIsCountedAndTheReaderStartsClean) {
  const Bytes whole = encode_state(moving(kSimStateId), {.sequence = 1});
  FrameReader reader;
  const auto none = read_all(reader, Bytes(whole.begin(), whole.begin() + 40));
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(reader.counts().partial_frame, 1u);
  const auto next = read_all(reader, encode_state(moving(kSimStateId), {.sequence = 2}));
  ASSERT_EQ(next.size(), 1u);
  EXPECT_EQ(next[0].sequence, 2);
}

TEST(MavlinkFrame, AKnownIdWithAnImpossibleLengthIsNotTakenForAFrame) {
  // A MAVLink 1 header naming SIMSTATE with 10 bytes (it has 44), then a real frame.
  const Bytes fake = bytes_of("fe 0a 00 01 01 a4");
  FrameReader reader;
  const auto frames = read_all(reader, fake + encode_state(moving(kSimstateId), {.version = 1, .sequence = 5}));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].sequence, 5);
  EXPECT_EQ(reader.counts().bad_length, 1u);
}

}  // namespace mavlink_frame_test
}  // namespace
}  // namespace gpsemu::sources::mavlink
