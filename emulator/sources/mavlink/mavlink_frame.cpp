#include "emulator/sources/mavlink/mavlink_frame.hpp"

#include <algorithm>
#include <cstring>

namespace gpsemu::sources::mavlink {
namespace {

bool is_start(std::uint8_t b) { return b == kStartV1 || b == kStartV2; }

}  // namespace

const MessageInfo* find_message(std::uint32_t id) {
  for (const MessageInfo& m : kMessages) {
    if (m.id == id) return &m;
  }
  return nullptr;
}

std::uint16_t crc_x25(std::uint8_t byte, std::uint16_t crc) {
  std::uint8_t t = static_cast<std::uint8_t>(byte ^ (crc & 0xFF));
  t = static_cast<std::uint8_t>(t ^ (t << 4));
  return static_cast<std::uint16_t>((crc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4));
}

std::uint16_t crc_x25(std::span<const std::uint8_t> bytes, std::uint16_t crc) {
  for (const std::uint8_t b : bytes) crc = crc_x25(b, crc);
  return crc;
}

FrameReader::FrameReader() { buffer_.reserve(4 * kMaxFrameBytes); }

void FrameReader::feed(std::span<const std::uint8_t> bytes) {
  compact();
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

void FrameReader::finish() { ended_ = true; }

void FrameReader::compact() {
  if (start_ == 0) return;
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(start_));
  start_ = 0;
}

std::optional<Frame> FrameReader::next() {
  for (;;) {
    const auto first = std::find_if(buffer_.begin() + static_cast<std::ptrdiff_t>(start_), buffer_.end(), is_start);
    const auto at = static_cast<std::size_t>(first - buffer_.begin());
    counts_.garbage_bytes += at - start_;
    start_ = at;
    if (start_ == buffer_.size()) {
      buffer_.clear();
      start_ = 0;
      ended_ = false;
      return std::nullopt;
    }
    Frame frame;
    switch (examine(frame)) {
      case Step::frame: return frame;
      case Step::skipped: continue;
      case Step::need_more: compact(); return std::nullopt;
    }
  }
}

FrameReader::Step FrameReader::examine(Frame& out) {
  const std::uint8_t* b = buffer_.data() + start_;
  const std::size_t available = buffer_.size() - start_;
  const bool v2 = b[0] == kStartV2;
  const std::size_t header = v2 ? kHeaderV2Bytes : kHeaderV1Bytes;
  // Input ended inside what may be a frame: count it once, then look for frames after its start byte.
  const auto cut_short = [this] {
    ++counts_.partial_frame;
    ++counts_.garbage_bytes;
    skip(1);
    return Step::skipped;
  };
  if (available < header) return ended_ ? cut_short() : Step::need_more;

  const std::uint8_t length = b[1];
  const std::uint8_t incompat = v2 ? b[2] : 0;
  if ((incompat & ~kIncompatSigned) != 0) {
    ++counts_.unsupported_flags;
    skip(1);
    return Step::skipped;
  }
  const bool is_signed = (incompat & kIncompatSigned) != 0;
  const std::uint32_t id = v2 ? (b[7] | (b[8] << 8) | (static_cast<std::uint32_t>(b[9]) << 16)) : b[5];
  const MessageInfo* info = find_message(id);
  if (info != nullptr) {
    // MAVLink 1 carries the base fields exactly; MAVLink 2 at least one byte, at most all fields.
    const bool length_ok = v2 ? (length >= 1 && length <= info->full_length) : length == info->base_length;
    if (!length_ok) {
      ++counts_.bad_length;
      ++counts_.garbage_bytes;
      skip(1);
      return Step::skipped;
    }
  }
  const std::size_t total = header + length + kCrcBytes + (is_signed ? kSignatureBytes : 0);
  if (available < total) return ended_ ? cut_short() : Step::need_more;

  if (info == nullptr) {
    // Unchecked: trusted when the next byte starts a frame or the input ends right there.
    if (available == total && !ended_) return Step::need_more;
    if (available > total && !is_start(b[total])) {
      ++counts_.garbage_bytes;
      skip(1);
      return Step::skipped;
    }
    ++counts_.unknown_message;
    skip(total);
    return Step::skipped;
  }

  std::uint16_t crc = crc_x25(std::span<const std::uint8_t>(b + 1, header - 1 + length));
  crc = crc_x25(info->crc_extra, crc);
  const std::uint16_t sent = static_cast<std::uint16_t>(b[header + length] | (b[header + length + 1] << 8));
  if (crc != sent) {
    ++counts_.bad_crc;
    skip(total);
    return Step::skipped;
  }
  if (is_signed) {
    ++counts_.signed_frame;
    skip(total);
    return Step::skipped;
  }
  out.version = v2 ? 2 : 1;
  out.sequence = v2 ? b[4] : b[2];
  out.system_id = v2 ? b[5] : b[3];
  out.component_id = v2 ? b[6] : b[4];
  out.message_id = id;
  out.wire_length = length;
  out.payload.fill(0);
  std::memcpy(out.payload.data(), b + header, length);
  ++counts_.frames;
  skip(total);
  return Step::frame;
}

}  // namespace gpsemu::sources::mavlink
