// RTCM 3 framing (RTCM 10403.3 §4): preamble 0xD3, 6 reserved zero bits and a 10-bit payload
// length, the payload, and a CRC-24Q over header and payload. Splits frames out of a byte stream
// (a base station's socket, or a u-blox port where the client interleaves RTCM3 with UBX and
// NMEA), incrementally: chunks may end anywhere; memory is bounded whatever the input. Writes
// frames too (tests, a base's output). Pure: bytes in, values out. What a frame says is decoded by
// rtcm3_messages.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gpsemu::rtk {

inline constexpr std::uint8_t rtcm3_preamble = 0xD3;
/// Bytes of a frame around its payload: preamble, 2 length bytes, 3 CRC bytes.
inline constexpr std::size_t rtcm3_overhead_bytes = 6;
/// The 10-bit length field's largest value.
inline constexpr std::size_t rtcm3_max_payload_bytes = 1023;

/// CRC-24Q (polynomial 0x1864CFB, initial value 0) of `bytes`, as RTCM3 and SBAS use it.
[[nodiscard]] std::uint32_t crc24q(std::string_view bytes);
/// Appends the frame of `payload` (at most rtcm3_max_payload_bytes; longer is cut) to `out`.
void append_rtcm3_frame(std::string& out, std::string_view payload);
[[nodiscard]] std::string rtcm3_frame_bytes(std::string_view payload);

/// One checked RTCM3 frame: its payload (message type in the first 12 bits).
struct Rtcm3Frame {
  std::string payload;
  /// DF002, the message number (1005, 1077, ...); 0 for a payload shorter than 2 bytes.
  [[nodiscard]] std::uint16_t message_type() const;
  friend bool operator==(const Rtcm3Frame&, const Rtcm3Frame&) = default;
};

/// Assembles one frame byte by byte from its preamble: the piece a stream reader (Rtcm3Reader,
/// the u-blox input's FrameReader) embeds. Feed the preamble first; each later byte says whether
/// the frame goes on, is complete, failed its CRC (dropped), or was no frame at all (a length
/// byte with reserved bits set: the 0xD3 was a data byte; that last byte is not consumed).
class Rtcm3Framer {
 public:
  enum class Step { more, frame, bad_crc, not_rtcm };
  /// Consumes `byte` of a frame started with the preamble (the first byte pushed must be 0xD3).
  Step push(std::uint8_t byte);
  /// The frame completed by the last push that returned Step::frame (moved out).
  [[nodiscard]] Rtcm3Frame take();
  /// Bytes of the frame under way (0 between frames).
  [[nodiscard]] std::size_t pending_bytes() const { return bytes_.size(); }

 private:
  std::string bytes_;  // from the preamble
  std::size_t payload_bytes_ = 0;
  Rtcm3Frame done_;
};

/// What an Rtcm3Reader has seen. Frames by message type are counted up to the 12-bit range.
struct Rtcm3Stats {
  std::uint64_t frames_ok = 0;      ///< frames with a good CRC
  std::uint64_t bad_crc = 0;        ///< complete frames whose CRC does not match (dropped)
  std::uint64_t garbage_bytes = 0;  ///< bytes outside any frame
  std::array<std::uint64_t, 4096> by_type{};  ///< frames_ok by message type (DF002)
  void count(const Rtcm3Frame& frame) {
    ++frames_ok;
    ++by_type[frame.message_type() & 0xFFFu];
  }
};

/// Splits a byte stream of RTCM3 (a base station's stream) into checked frames. A frame with a
/// bad CRC is dropped and counted; bytes before a preamble are counted as garbage.
class Rtcm3Reader {
 public:
  /// Consumes `bytes` and returns the frames they complete, in stream order.
  [[nodiscard]] std::vector<Rtcm3Frame> feed(std::string_view bytes);
  [[nodiscard]] const Rtcm3Stats& stats() const { return stats_; }

 private:
  void consume(std::uint8_t byte, std::vector<Rtcm3Frame>& out);
  bool in_frame_ = false;
  Rtcm3Framer framer_;
  Rtcm3Stats stats_;
};

}  // namespace gpsemu::rtk
