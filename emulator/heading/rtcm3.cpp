// RTCM 3 framing, bit writer and scanner (see rtcm3.hpp).
#include "emulator/heading/rtcm3.hpp"

#include <stdexcept>

namespace gpsemu::heading {
namespace {

constexpr unsigned char kPreamble = 0xD3;
constexpr std::size_t kHeaderBytes = 3;
constexpr std::size_t kCrcBytes = 3;

}  // namespace

std::uint32_t crc24q(std::string_view bytes) {
  std::uint32_t crc = 0;
  for (const char ch : bytes) {
    crc ^= static_cast<std::uint32_t>(static_cast<unsigned char>(ch)) << 16;
    for (int i = 0; i < 8; ++i) {
      crc <<= 1;
      if (crc & 0x1000000u) crc ^= 0x1864CFBu;
    }
  }
  return crc & 0xFFFFFFu;
}

std::string rtcm3_frame(std::string_view payload) {
  if (payload.size() > kRtcm3MaxPayloadBytes) throw std::invalid_argument("RTCM 3 payload over 1023 bytes");
  std::string frame;
  frame.reserve(payload.size() + kHeaderBytes + kCrcBytes);
  frame += static_cast<char>(kPreamble);
  frame += static_cast<char>((payload.size() >> 8) & 0x03);
  frame += static_cast<char>(payload.size() & 0xFF);
  frame += payload;
  const std::uint32_t crc = crc24q(frame);
  frame += static_cast<char>((crc >> 16) & 0xFF);
  frame += static_cast<char>((crc >> 8) & 0xFF);
  frame += static_cast<char>(crc & 0xFF);
  return frame;
}

void BitWriter::put_unsigned(std::uint64_t value, int bits) {
  for (int i = bits - 1; i >= 0; --i) {
    if (bits_ % 8 == 0) bytes_ += '\0';
    if ((value >> i) & 1u) bytes_.back() = static_cast<char>(static_cast<unsigned char>(bytes_.back()) | (0x80u >> (bits_ % 8)));
    ++bits_;
  }
}

void BitWriter::put_signed(std::int64_t value, int bits) {
  const std::uint64_t mask = bits >= 64 ? ~0ull : (1ull << bits) - 1;
  put_unsigned(static_cast<std::uint64_t>(value) & mask, bits);
}

// A stray 0xD3 holds the frames behind it until its own length is in (at most 1029 bytes), then
// the search starts again at the next 0xD3 of what is pending.
std::vector<int> Rtcm3Scanner::feed(std::string_view bytes) {
  std::vector<int> found;
  for (const char ch : bytes) {
    if (pending_.empty() && static_cast<unsigned char>(ch) != kPreamble) continue;
    pending_ += ch;
    // Resolve what is pending: a whole frame, a bad start (skip its 0xD3), or wait for more.
    while (!pending_.empty()) {
      if (pending_.size() < kHeaderBytes) break;
      const auto b1 = static_cast<unsigned char>(pending_[1]);
      const std::size_t length = (static_cast<std::size_t>(b1 & 0x03) << 8) | static_cast<unsigned char>(pending_[2]);
      const std::size_t total = kHeaderBytes + length + kCrcBytes;
      const bool bad_header = (b1 & 0xFC) != 0;  // the 6 reserved bits are 0
      if (!bad_header && pending_.size() < total) break;
      if (!bad_header) {
        const std::uint32_t crc = crc24q(std::string_view(pending_).substr(0, kHeaderBytes + length));
        const auto at = [this](std::size_t i) { return static_cast<std::uint32_t>(static_cast<unsigned char>(pending_[i])); };
        const std::uint32_t sent = (at(total - 3) << 16) | (at(total - 2) << 8) | at(total - 1);
        if (crc == sent) {
          ++stats_.frames;
          if (length >= 2) found.push_back(static_cast<int>((at(3) << 4) | (at(4) >> 4)));
          // What follows the frame (already buffered): from its next 0xD3 on.
          const std::size_t next = pending_.find(static_cast<char>(kPreamble), total);
          pending_ = next == std::string::npos ? std::string{} : pending_.substr(next);
          continue;
        }
        ++stats_.bad_crc;
      }
      // Not a frame at this 0xD3: look again from the next one.
      const std::size_t next = pending_.find(static_cast<char>(kPreamble), 1);
      pending_ = next == std::string::npos ? std::string{} : pending_.substr(next);
    }
  }
  return found;
}

}  // namespace gpsemu::heading
