// UBX framing and the client stream reader (see frame.hpp).
#include "emulator/ubx/frame.hpp"

#include "emulator/ubx/bytes.hpp"

namespace gpsemu::ubx {

std::uint16_t fletcher_checksum(std::string_view body) {
  std::uint8_t a = 0;
  std::uint8_t b = 0;
  for (const char c : body) {
    a = static_cast<std::uint8_t>(a + static_cast<std::uint8_t>(c));
    b = static_cast<std::uint8_t>(b + a);
  }
  return static_cast<std::uint16_t>(a | (b << 8));
}

void append_frame(std::string& out, MessageId id, std::string_view payload) {
  out.push_back(static_cast<char>(sync1));
  out.push_back(static_cast<char>(sync2));
  const std::size_t body_start = out.size();
  put_u1(out, id.msg_class);
  put_u1(out, id.msg_id);
  put_u2(out, static_cast<std::uint32_t>(payload.size()));
  out.append(payload);
  put_u2(out, fletcher_checksum(std::string_view(out).substr(body_start)));
}

std::string frame_bytes(MessageId id, std::string_view payload) {
  std::string out;
  append_frame(out, id, payload);
  return out;
}

std::vector<ClientMessage> FrameReader::feed(std::string_view bytes) {
  std::vector<ClientMessage> out;
  for (const char c : bytes) consume(static_cast<std::uint8_t>(c), out);
  return out;
}

void FrameReader::end_sentence(std::vector<ClientMessage>& out) {
  nmea::Result<nmea::Sentence> parsed = nmea::parse_sentence(sentence_);
  if (parsed.ok()) {
    ++stats_.sentences_ok;
    out.emplace_back(std::move(parsed).value());
  } else {
    ++stats_.bad_sentences;
  }
  sentence_.clear();
  state_ = State::between;
}

// A header announced too long a payload: the sync may have been a data byte. Scan again from the
// byte after the first sync byte.
void FrameReader::rescan_after_first_sync(std::vector<ClientMessage>& out) {
  ++stats_.too_long;
  const std::string rest = frame_.substr(1);
  frame_.clear();
  state_ = State::between;
  for (const char c : rest) consume(static_cast<std::uint8_t>(c), out);
}

void FrameReader::consume(std::uint8_t byte, std::vector<ClientMessage>& out) {
  switch (state_) {
    case State::between:
      if (byte == sync1) {
        frame_.assign(1, static_cast<char>(byte));
        state_ = State::sync;
      } else if (byte == '$') {
        sentence_.assign(1, '$');
        state_ = State::sentence;
      } else if (byte == rtk::rtcm3_preamble) {
        (void)rtcm_.push(byte);
        state_ = State::rtcm3;
      } else {
        ++stats_.garbage_bytes;
      }
      return;
    case State::sync:
      if (byte == sync2) {
        frame_.push_back(static_cast<char>(byte));
        state_ = State::header;
      } else {
        ++stats_.garbage_bytes;  // the lone 0xB5
        state_ = State::between;
        consume(byte, out);
      }
      return;
    case State::header:
      frame_.push_back(static_cast<char>(byte));
      if (frame_.size() == 6) {
        payload_bytes_ = get_u2(frame_, 4);
        if (payload_bytes_ > max_client_payload_bytes) {
          rescan_after_first_sync(out);
          return;
        }
        state_ = payload_bytes_ == 0 ? State::checksum : State::payload;
      }
      return;
    case State::payload:
      frame_.push_back(static_cast<char>(byte));
      if (frame_.size() == 6 + payload_bytes_) state_ = State::checksum;
      return;
    case State::checksum:
      frame_.push_back(static_cast<char>(byte));
      if (frame_.size() == frame_overhead_bytes + payload_bytes_) {
        const std::string_view body = std::string_view(frame_).substr(2, 4 + payload_bytes_);
        if (get_u2(frame_, 6 + payload_bytes_) == fletcher_checksum(body)) {
          ++stats_.frames_ok;
          out.emplace_back(Frame{{get_u1(frame_, 2), get_u1(frame_, 3)}, frame_.substr(6, payload_bytes_)});
        } else {
          ++stats_.bad_checksum;
        }
        frame_.clear();
        state_ = State::between;
      }
      return;
    case State::rtcm3:
      switch (rtcm_.push(byte)) {
        case rtk::Rtcm3Framer::Step::more:
          return;
        case rtk::Rtcm3Framer::Step::frame:
          ++stats_.rtcm_ok;
          out.emplace_back(rtcm_.take());
          break;
        case rtk::Rtcm3Framer::Step::bad_crc:
          ++stats_.rtcm_bad_crc;
          break;
        case rtk::Rtcm3Framer::Step::not_rtcm:
          ++stats_.garbage_bytes;  // the lone 0xD3
          state_ = State::between;
          consume(byte, out);
          return;
      }
      state_ = State::between;
      return;
    case State::sentence:
      if (byte == '\r' || byte == '\n') {
        end_sentence(out);
        ++stats_.garbage_bytes;  // the line end
      } else if (byte < 0x20 || byte > 0x7E || byte == '$' || sentence_.size() >= nmea::max_parse_chars) {
        ++stats_.bad_sentences;
        sentence_.clear();
        state_ = State::between;
        consume(byte, out);  // a sync byte or a new '$' starts something new
      } else {
        sentence_.push_back(static_cast<char>(byte));
      }
      return;
  }
}

}  // namespace gpsemu::ubx
