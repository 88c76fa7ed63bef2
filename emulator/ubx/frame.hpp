// UBX framing: sync 0xB5 0x62, class, id, little-endian payload length, payload, 8-bit Fletcher
// checksum over class..payload. Writes frames and reads them back from a client's byte stream
// that may interleave NMEA text (PUBX commands), RTCM3 corrections (0xD3 frames: an autopilot
// injecting them through the GPS port) and garbage. Pure: bytes in, values out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "emulator/rtk/rtcm3_reader.hpp"
#include "nmea/parse.hpp"

namespace gpsemu::ubx {

inline constexpr std::uint8_t sync1 = 0xB5;
inline constexpr std::uint8_t sync2 = 0x62;
/// Bytes of a frame around its payload: 2 sync, class, id, 2 length, 2 checksum.
inline constexpr std::size_t frame_overhead_bytes = 8;
/// Longest payload the reader accepts from a client (a CFG-VALSET holds at most 64 keys).
inline constexpr std::size_t max_client_payload_bytes = 1024;

/// A message's class and id ("NAV-PVT" is {0x01, 0x07}).
struct MessageId {
  std::uint8_t msg_class = 0;
  std::uint8_t msg_id = 0;
  friend constexpr bool operator==(MessageId, MessageId) = default;
  friend constexpr auto operator<=>(MessageId, MessageId) = default;
};

namespace msg {
inline constexpr MessageId nav_posecef{0x01, 0x01};
inline constexpr MessageId nav_posllh{0x01, 0x02};
inline constexpr MessageId nav_status{0x01, 0x03};
inline constexpr MessageId nav_dop{0x01, 0x04};
inline constexpr MessageId nav_sol{0x01, 0x06};
inline constexpr MessageId nav_pvt{0x01, 0x07};
inline constexpr MessageId nav_velecef{0x01, 0x11};
inline constexpr MessageId nav_velned{0x01, 0x12};
inline constexpr MessageId nav_hpposllh{0x01, 0x14};
inline constexpr MessageId nav_timegps{0x01, 0x20};
inline constexpr MessageId nav_timeutc{0x01, 0x21};
inline constexpr MessageId nav_clock{0x01, 0x22};
inline constexpr MessageId nav_timels{0x01, 0x26};
inline constexpr MessageId nav_svinfo{0x01, 0x30};
inline constexpr MessageId nav_sbas{0x01, 0x32};
inline constexpr MessageId nav_sat{0x01, 0x35};
inline constexpr MessageId nav_cov{0x01, 0x36};
inline constexpr MessageId nav_svin{0x01, 0x3B};
inline constexpr MessageId nav_relposned{0x01, 0x3C};
inline constexpr MessageId nav_sig{0x01, 0x43};
inline constexpr MessageId nav_eoe{0x01, 0x61};
inline constexpr MessageId rxm_rtcm{0x02, 0x32};
inline constexpr MessageId ack_nak{0x05, 0x00};
inline constexpr MessageId ack_ack{0x05, 0x01};
inline constexpr MessageId cfg_prt{0x06, 0x00};
inline constexpr MessageId cfg_msg{0x06, 0x01};
inline constexpr MessageId cfg_rst{0x06, 0x04};
inline constexpr MessageId cfg_rate{0x06, 0x08};
inline constexpr MessageId cfg_cfg{0x06, 0x09};
inline constexpr MessageId cfg_sbas{0x06, 0x16};
inline constexpr MessageId cfg_nav5{0x06, 0x24};
inline constexpr MessageId cfg_gnss{0x06, 0x3E};
inline constexpr MessageId cfg_valset{0x06, 0x8A};
inline constexpr MessageId cfg_valget{0x06, 0x8B};
inline constexpr MessageId cfg_valdel{0x06, 0x8C};
inline constexpr MessageId mon_ver{0x0A, 0x04};
inline constexpr MessageId mon_hw{0x0A, 0x09};
inline constexpr MessageId mon_hw2{0x0A, 0x0B};
inline constexpr MessageId mon_rf{0x0A, 0x38};
inline constexpr MessageId nmea_class_first{0xF0, 0x00};  ///< NMEA standard sentences: class 0xF0
}  // namespace msg

/// One UBX message: its id and payload bytes.
struct Frame {
  MessageId id;
  std::string payload;
  friend bool operator==(const Frame&, const Frame&) = default;
};

/// The two checksum bytes (CK_A, CK_B) of `body` (class, id, length and payload).
[[nodiscard]] std::uint16_t fletcher_checksum(std::string_view body);
/// Appends the frame of `id` with `payload` to `out`.
void append_frame(std::string& out, MessageId id, std::string_view payload);
[[nodiscard]] std::string frame_bytes(MessageId id, std::string_view payload);

/// What a FrameReader has seen: frames and sentences by outcome, and the bytes outside any frame
/// or '$' line (CR and LF between lines included).
struct FrameStats {
  std::uint64_t frames_ok = 0;        ///< UBX frames returned
  std::uint64_t bad_checksum = 0;     ///< complete UBX frames whose checksum does not match
  std::uint64_t too_long = 0;         ///< UBX headers announcing more than max_client_payload_bytes
  std::uint64_t sentences_ok = 0;     ///< NMEA sentences returned (PUBX or any other)
  std::uint64_t bad_sentences = 0;    ///< '$' lines that are no valid sentence
  std::uint64_t garbage_bytes = 0;    ///< bytes outside any frame or line
  std::uint64_t rtcm_ok = 0;          ///< RTCM3 frames returned
  std::uint64_t rtcm_bad_crc = 0;     ///< complete RTCM3 frames whose CRC-24Q does not match (dropped)
};

/// One thing a client wrote: a UBX frame, an NMEA sentence ($PUBX,40 / $PUBX,41 ...) or an RTCM3
/// frame (corrections).
using ClientMessage = std::variant<Frame, nmea::Sentence, rtk::Rtcm3Frame>;

/// Splits a client's bytes into checked UBX frames and NMEA sentences, incrementally: chunks may
/// end anywhere. A frame with a bad checksum is dropped; a header announcing a too long payload
/// is dropped and the search for a sync resumes at the byte after its first sync byte. A '$'
/// line ends at CR or LF and is abandoned at a byte outside printable ASCII or past
/// nmea::max_parse_chars. An RTCM3 frame starts at 0xD3 (rtk::Rtcm3Framer): one with a bad CRC is
/// dropped and counted; a 0xD3 whose length byte has reserved bits set is garbage and the search
/// resumes at that byte. Memory is bounded whatever the input.
class FrameReader {
 public:
  /// Consumes `bytes` and returns the messages they complete, in stream order.
  [[nodiscard]] std::vector<ClientMessage> feed(std::string_view bytes);
  [[nodiscard]] const FrameStats& stats() const { return stats_; }

 private:
  enum class State { between, sync, header, payload, checksum, sentence, rtcm3 };
  void consume(std::uint8_t byte, std::vector<ClientMessage>& out);
  void end_sentence(std::vector<ClientMessage>& out);
  void rescan_after_first_sync(std::vector<ClientMessage>& out);

  State state_ = State::between;
  std::string frame_;     // from the first sync byte
  std::size_t payload_bytes_ = 0;
  std::string sentence_;  // from '$', at most nmea::max_parse_chars
  rtk::Rtcm3Framer rtcm_;
  FrameStats stats_;
};

}  // namespace gpsemu::ubx
