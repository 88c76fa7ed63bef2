// RTCM 3 framing for the moving-base pair: the transport layer (preamble 0xD3, 6 reserved bits,
// 10-bit length, payload, CRC-24Q), a big-endian bit writer for message bodies, and a scanner that
// finds whole, checked frames in what a client writes to the rover (the autopilot forwarding the
// base's corrections, between its UBX and NMEA bytes). Pure: bytes in, bytes or counts out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gpsemu::heading {

/// CRC-24Q (Qualcomm; polynomial 0x1864CFB, initial 0) of `bytes`, as RTCM 3 and SBAS use it.
[[nodiscard]] std::uint32_t crc24q(std::string_view bytes);

/// The longest RTCM 3 payload (bytes): 10 bits of length.
inline constexpr std::size_t kRtcm3MaxPayloadBytes = 1023;

/// A whole frame around `payload` (at most kRtcm3MaxPayloadBytes): D3, length, payload, CRC.
[[nodiscard]] std::string rtcm3_frame(std::string_view payload);

/// Writes unsigned and two's-complement fields of any width (1..64 bits), most significant bit
/// first, as RTCM 3 data fields are laid out; the last byte is padded with zeros.
class BitWriter {
 public:
  void put_unsigned(std::uint64_t value, int bits);
  void put_signed(std::int64_t value, int bits);
  [[nodiscard]] std::size_t bit_count() const { return bits_; }
  /// The bytes written so far (the last one zero-padded).
  [[nodiscard]] const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
  std::size_t bits_ = 0;
};

/// What an Rtcm3Scanner has seen.
struct Rtcm3ScanStats {
  std::uint64_t frames = 0;     ///< frames with a good CRC
  std::uint64_t bad_crc = 0;    ///< frames whose CRC did not match (dropped)
};

/// Finds RTCM 3 frames in a byte stream that also carries other protocols, incrementally (a
/// frame may arrive in pieces). A 0xD3 that does not start a frame with a good CRC is skipped
/// byte by byte, so UBX or NMEA bytes around the frames are harmless. Memory is bounded by one
/// frame.
class Rtcm3Scanner {
 public:
  /// The message numbers (the payload's first 12 bits) of the frames `bytes` completes.
  [[nodiscard]] std::vector<int> feed(std::string_view bytes);
  [[nodiscard]] const Rtcm3ScanStats& stats() const { return stats_; }

 private:
  std::string pending_;  ///< from a 0xD3 on, at most one frame
  Rtcm3ScanStats stats_;
};

}  // namespace gpsemu::heading
