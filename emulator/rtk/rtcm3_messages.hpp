// What an RTCM3 frame says (RTCM 10403.3): the message type, the reference station, the base's
// antenna position (1005/1006), the MSM header of an observation message (1071..1137: GNSS, MSM
// number, epoch, satellites, signals, cells; the body's length checked against them), the GLONASS
// biases (1230) and u-blox's proprietary 4072 sub-type. Only what an RTK rover's state needs; the
// observations themselves are not decoded. Also the encoders of the same fields (tests, fuzz seeds,
// a base's output). Pure: bytes in, values out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace gpsemu::rtk {

/// Reads big-endian bit fields (RTCM's DF layout) from a payload; reads past the end yield 0 and
/// set `overrun`.
class BitReader {
 public:
  explicit BitReader(std::string_view bytes) : bytes_(bytes) {}
  [[nodiscard]] std::uint64_t u(int bits);
  [[nodiscard]] std::int64_t s(int bits);  ///< two's complement
  void skip(std::size_t bits) { at_ += bits; }
  [[nodiscard]] std::size_t position_bits() const { return at_; }
  [[nodiscard]] bool overrun() const { return at_ > bytes_.size() * 8; }

 private:
  std::string_view bytes_;
  std::size_t at_ = 0;
};

/// Appends big-endian bit fields; pad() fills the last byte with zero bits.
class BitWriter {
 public:
  void u(std::uint64_t value, int bits);
  void s(std::int64_t value, int bits) { u(static_cast<std::uint64_t>(value), bits); }
  [[nodiscard]] std::string bytes() const { return bytes_; }

 private:
  std::string bytes_;
  int used_bits_in_last_ = 8;
};

enum class Gnss : std::uint8_t { gps, glonass, galileo, sbas, qzss, beidou, navic };
[[nodiscard]] std::string_view gnss_name(Gnss gnss);

/// A reference station's antenna reference point (1005) and antenna height (1006), ECEF metres.
struct BasePosition {
  std::uint16_t station_id = 0;
  double ecef_x_m = 0, ecef_y_m = 0, ecef_z_m = 0;
  double antenna_height_m = 0;  ///< 1006 only; 0 for 1005
};

/// The header of a multiple signal message (MSM1..7).
struct MsmHeader {
  Gnss gnss = Gnss::gps;
  int msm = 0;                    ///< 1..7 (MSM4: pseudorange + phase + CNR, MSM7: high resolution)
  std::uint32_t epoch_time = 0;   ///< DF004 and its kin: ms of the GNSS week / day (as sent)
  bool more_follow = false;       ///< multiple message bit: more MSM of this epoch follow
  int satellites = 0;
  int signals = 0;
  int cells = 0;                  ///< satellite x signal pairs observed
};

/// One decoded frame. `valid` is false when the payload is shorter than its type requires (the
/// frame's CRC was good, so the sender wrote it wrong): such a message is counted, not used.
struct Rtcm3Message {
  std::uint16_t type = 0;
  std::optional<std::uint16_t> station_id;  ///< DF003 (types that carry one)
  std::optional<BasePosition> base;         ///< 1005 / 1006
  std::optional<MsmHeader> msm;             ///< 1071..1137
  std::optional<std::uint16_t> subtype;     ///< 4072 (u-blox proprietary: 0 = reference station PVT)
  bool valid = true;
};

/// Decodes the fields above from a frame's payload.
[[nodiscard]] Rtcm3Message decode_rtcm3(std::string_view payload);
/// "1005 base position", "1077 GPS MSM7", "1230 GLONASS biases", "4072.0 u-blox", "1019 other".
[[nodiscard]] std::string describe(const Rtcm3Message& message);

/// The payload of a 1005 (antenna_height_m ignored) or 1006 message for `base`.
[[nodiscard]] std::string encode_base_position(const BasePosition& base, bool with_height);
/// The payload of an MSM of type `type` (1071..1137) whose masks hold `satellites` satellites
/// (1..n, at most 64) and `signals` signals (ids 2..n+1, at most 31), all cells observed (at most 64): the header and the body's length as a receiver sends
/// them, MSM4..7 with each satellite's rough range 70 + its index ms, every other field zero.
[[nodiscard]] std::string encode_msm(std::uint16_t type, std::uint16_t station_id, std::uint32_t epoch_time,
                                     int satellites, int signals);
/// The payload of a 1230 (GLONASS code-phase biases): not aligned, a bias of 0 m for each signal of
/// `signals_mask` (DF423: bit 3 L1 C/A, 2 L1 P, 1 L2 C/A, 0 L2 P); none by default.
[[nodiscard]] std::string encode_1230(std::uint16_t station_id, unsigned signals_mask = 0);

}  // namespace gpsemu::rtk
