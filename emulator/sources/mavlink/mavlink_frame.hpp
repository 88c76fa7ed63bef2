// MAVLink framing, pure: bytes in (a UDP datagram, or whatever a TCP read returned), checked frames
// out. Our own reader of the wire format (mavlink.io "Packet Serialization"), no generated code:
//
//   MAVLink 1: 0xFE len seq sysid compid msgid(1)              payload(len) crc(2)
//   MAVLink 2: 0xFD len incompat compat seq sysid compid msgid(3) payload(len) crc(2) [signature(13)]
//
// The CRC is X.25 (CRC-16/MCRF4XX) over everything after the start byte, then the message's
// CRC_EXTRA (a hash of its definition: the sender and we must agree on the field layout). Only the
// messages in kMessages can be checked; a frame of another id is skipped by its length and counted,
// trusted only when the byte after it starts another frame (or the input ends there), so garbage
// holding a start byte cannot make the reader jump over real frames. A MAVLink 2 payload may come
// with its trailing zero bytes cut off: it is zero-extended to the message's length. Signed frames
// (incompat flag 0x01) are checked, skipped with their 13-byte signature and counted, never used
// (we hold no key to verify them); frames with unknown incompat flags are refused. Bad CRCs,
// wrong lengths and bytes between frames are counted and skipped; the reader resynchronises on the
// next start byte. No I/O, no clocks, no logging: unit- and fuzz-tested.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace gpsemu::sources::mavlink {

inline constexpr std::uint8_t kStartV1 = 0xFE;
inline constexpr std::uint8_t kStartV2 = 0xFD;
inline constexpr std::uint8_t kIncompatSigned = 0x01;  ///< MAVLINK_IFLAG_SIGNED
inline constexpr std::size_t kHeaderV1Bytes = 6;       ///< start byte to msgid
inline constexpr std::size_t kHeaderV2Bytes = 10;
inline constexpr std::size_t kCrcBytes = 2;
inline constexpr std::size_t kSignatureBytes = 13;
inline constexpr std::size_t kMaxPayloadBytes = 255;
inline constexpr std::size_t kMaxFrameBytes = kHeaderV2Bytes + kMaxPayloadBytes + kCrcBytes + kSignatureBytes;

/// Message ids this project reads (message_definitions/v1.0/common.xml, ardupilotmega.xml).
inline constexpr std::uint32_t kSimStateId = 108;            ///< SIM_STATE (common)
inline constexpr std::uint32_t kHilStateQuaternionId = 115;  ///< HIL_STATE_QUATERNION (common)
inline constexpr std::uint32_t kSimstateId = 164;            ///< SIMSTATE (ardupilotmega)
/// ATTITUDE (common): read for its time_boot_ms, the sender time of the SIMSTATE sent with it.
inline constexpr std::uint32_t kAttitudeId = 30;

/// What the reader knows of a message: its CRC_EXTRA and payload lengths (bytes).
struct MessageInfo {
  std::uint32_t id = 0;
  const char* name = "";
  std::uint8_t crc_extra = 0;
  std::uint8_t base_length = 0;  ///< without extension fields: MAVLink 1's length
  std::uint8_t full_length = 0;  ///< with extension fields: MAVLink 2's longest payload
};

/// SIM_STATE, HIL_STATE_QUATERNION, SIMSTATE (the states, in this order), ATTITUDE. CRC_EXTRA
/// computed from the XML definitions with the generator's rule (the name, then each base field's
/// type and name in wire order).
inline constexpr std::array<MessageInfo, 4> kMessages{{
    {kSimStateId, "SIM_STATE", 32, 84, 92},
    {kHilStateQuaternionId, "HIL_STATE_QUATERNION", 4, 64, 64},
    {kSimstateId, "SIMSTATE", 154, 44, 44},
    {kAttitudeId, "ATTITUDE", 39, 28, 28},
}};

/// The entry of kMessages for `id`, or nothing.
[[nodiscard]] const MessageInfo* find_message(std::uint32_t id);

/// X.25 CRC-16/MCRF4XX (poly 0x1021 reflected, init 0xFFFF, no final xor) continued over `bytes`.
[[nodiscard]] std::uint16_t crc_x25(std::span<const std::uint8_t> bytes, std::uint16_t crc = 0xFFFF);
[[nodiscard]] std::uint16_t crc_x25(std::uint8_t byte, std::uint16_t crc);

/// One checked frame of a known message.
struct Frame {
  int version = 2;                 ///< 1 or 2
  std::uint8_t sequence = 0;
  std::uint8_t system_id = 0;
  std::uint8_t component_id = 0;
  std::uint32_t message_id = 0;
  std::uint8_t wire_length = 0;    ///< payload bytes as sent (MAVLink 2 may cut trailing zeros)
  /// The payload zero-extended to the message's full length; payload[0, full_length) is valid.
  std::array<std::uint8_t, kMaxPayloadBytes> payload{};
};

/// What the reader skipped, by reason (running totals).
struct FrameCounts {
  std::uint64_t frames = 0;             ///< checked frames of known messages returned (ATTITUDE too)
  std::uint64_t unknown_message = 0;    ///< well-formed frames of other messages, skipped
  std::uint64_t bad_crc = 0;            ///< frames of known messages whose CRC did not match
  std::uint64_t bad_length = 0;         ///< a known message with a length it cannot have
  std::uint64_t signed_frame = 0;       ///< signed MAVLink 2 frames (checked, skipped with the signature)
  std::uint64_t unsupported_flags = 0;  ///< MAVLink 2 incompat flags other than signing
  std::uint64_t garbage_bytes = 0;      ///< bytes outside any frame (between frames, false start bytes)
  std::uint64_t partial_frame = 0;      ///< input ended (datagram end, connection closed) inside a frame
};

class FrameReader {
 public:
  FrameReader();

  /// Appends bytes; take the frames with next() before the next feed().
  void feed(std::span<const std::uint8_t> bytes);
  /// The next checked frame of a known message, or nothing until more bytes come. Frames that
  /// are skipped are counted in counts().
  [[nodiscard]] std::optional<Frame> next();
  /// The input ended (a datagram's end, a closed connection): what is left is counted and dropped
  /// (a frame of an unknown message that ends exactly here is counted as such, not as partial).
  void finish();

  [[nodiscard]] const FrameCounts& counts() const { return counts_; }

 private:
  enum class Step { frame, skipped, need_more };
  /// Looks at the frame starting at start_ (a start byte there).
  Step examine(Frame& out);
  void skip(std::size_t n) { start_ += n; }
  void compact();

  std::vector<std::uint8_t> buffer_;
  std::size_t start_ = 0;  ///< unread bytes are buffer_[start_, end)
  bool ended_ = false;     ///< inside finish(): no more bytes will come
  FrameCounts counts_;
};

}  // namespace gpsemu::sources::mavlink
