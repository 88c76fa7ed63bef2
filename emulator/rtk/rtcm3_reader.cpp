// RTCM3 framing and CRC-24Q (see rtcm3_reader.hpp).
#include "emulator/rtk/rtcm3_reader.hpp"

#include <utility>

namespace gpsemu::rtk {
namespace {

constexpr std::uint32_t kCrc24qPoly = 0x1864CFB;

constexpr std::array<std::uint32_t, 256> crc24q_table() {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t crc = i << 16;
    for (int bit = 0; bit < 8; ++bit) {
      crc <<= 1;
      if ((crc & 0x1000000) != 0) crc ^= kCrc24qPoly;
    }
    t[i] = crc & 0xFFFFFF;
  }
  return t;
}
constexpr std::array<std::uint32_t, 256> kCrcTable = crc24q_table();

}  // namespace

std::uint32_t crc24q(std::string_view bytes) {
  std::uint32_t crc = 0;
  for (const char c : bytes) {
    crc = ((crc << 8) & 0xFFFFFF) ^ kCrcTable[((crc >> 16) ^ static_cast<std::uint8_t>(c)) & 0xFF];
  }
  return crc;
}

void append_rtcm3_frame(std::string& out, std::string_view payload) {
  payload = payload.substr(0, rtcm3_max_payload_bytes);
  const std::size_t start = out.size();
  out.push_back(static_cast<char>(rtcm3_preamble));
  out.push_back(static_cast<char>((payload.size() >> 8) & 0x03));
  out.push_back(static_cast<char>(payload.size() & 0xFF));
  out.append(payload);
  const std::uint32_t crc = crc24q(std::string_view(out).substr(start));
  out.push_back(static_cast<char>((crc >> 16) & 0xFF));
  out.push_back(static_cast<char>((crc >> 8) & 0xFF));
  out.push_back(static_cast<char>(crc & 0xFF));
}

std::string rtcm3_frame_bytes(std::string_view payload) {
  std::string out;
  append_rtcm3_frame(out, payload);
  return out;
}

std::uint16_t Rtcm3Frame::message_type() const {
  if (payload.size() < 2) return 0;
  return static_cast<std::uint16_t>((static_cast<std::uint8_t>(payload[0]) << 4) |
                                    (static_cast<std::uint8_t>(payload[1]) >> 4));
}

Rtcm3Framer::Step Rtcm3Framer::push(std::uint8_t byte) {
  if (bytes_.size() == 1 && (byte & 0xFC) != 0) {
    bytes_.clear();  // reserved bits set: not a frame header
    return Step::not_rtcm;
  }
  bytes_.push_back(static_cast<char>(byte));
  if (bytes_.size() == 3) {
    payload_bytes_ = (static_cast<std::size_t>(static_cast<std::uint8_t>(bytes_[1])) << 8 |
                      static_cast<std::uint8_t>(bytes_[2])) & 0x3FF;
  }
  if (bytes_.size() < 3 || bytes_.size() < rtcm3_overhead_bytes + payload_bytes_) return Step::more;
  const std::size_t body = 3 + payload_bytes_;
  const std::uint32_t got = static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes_[body])) << 16 |
                            static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes_[body + 1])) << 8 |
                            static_cast<std::uint8_t>(bytes_[body + 2]);
  const bool ok = got == crc24q(std::string_view(bytes_).substr(0, body));
  if (ok) done_.payload = bytes_.substr(3, payload_bytes_);
  bytes_.clear();
  payload_bytes_ = 0;
  return ok ? Step::frame : Step::bad_crc;
}

Rtcm3Frame Rtcm3Framer::take() { return std::exchange(done_, Rtcm3Frame{}); }

std::vector<Rtcm3Frame> Rtcm3Reader::feed(std::string_view bytes) {
  std::vector<Rtcm3Frame> out;
  for (const char c : bytes) consume(static_cast<std::uint8_t>(c), out);
  return out;
}

void Rtcm3Reader::consume(std::uint8_t byte, std::vector<Rtcm3Frame>& out) {
  if (!in_frame_) {
    if (byte != rtcm3_preamble) {
      ++stats_.garbage_bytes;
      return;
    }
    in_frame_ = true;
    (void)framer_.push(byte);
    return;
  }
  switch (framer_.push(byte)) {
    case Rtcm3Framer::Step::more:
      return;
    case Rtcm3Framer::Step::frame:
      in_frame_ = false;
      out.push_back(framer_.take());
      stats_.count(out.back());
      return;
    case Rtcm3Framer::Step::bad_crc:
      in_frame_ = false;
      ++stats_.bad_crc;
      return;
    case Rtcm3Framer::Step::not_rtcm:
      in_frame_ = false;
      ++stats_.garbage_bytes;  // the lone preamble
      consume(byte, out);      // the byte may start a frame
      return;
  }
}

}  // namespace gpsemu::rtk
