// StreamReader: a byte-at-a-time state machine over a receiver's raw stream (see parse.hpp).
#include <string_view>

#include "nmea/parse.hpp"

namespace gpsemu::nmea {
namespace {

bool is_line_end(char c) { return c == '\r' || c == '\n'; }
bool is_printable(char c) { return c >= 0x20 && c <= 0x7E; }

}  // namespace

std::vector<Sentence> StreamReader::feed(std::string_view bytes) {
  std::vector<Sentence> out;
  for (const char byte : bytes) consume(byte, out);
  return out;
}

std::optional<Sentence> StreamReader::finish() {
  std::vector<Sentence> out;
  if (state_ == State::sentence) end_sentence(out);
  if (state_ == State::comment) ++stats_.comment_lines;
  state_ = State::between;
  at_line_start_ = true;
  comment_chars_ = 0;
  if (out.empty()) return std::nullopt;
  return std::move(out.front());
}

void StreamReader::consume(char byte, std::vector<Sentence>& out) {
  switch (state_) {
    case State::sentence:
      if (is_line_end(byte)) {
        end_sentence(out);
        state_ = State::between;
        at_line_start_ = true;
      } else if (byte == '$') {
        abandon_sentence();
        start_sentence();
      } else if (!is_printable(byte)) {
        abandon_sentence();
        state_ = State::between;
        at_line_start_ = false;
        ++stats_.garbage_bytes;  // the byte that interrupted it
      } else if (candidate_.size() >= max_parse_chars) {
        ++stats_.malformed;  // too long: the rest of the line is skipped
        candidate_.clear();
        state_ = State::rest_of_line;
        ++stats_.garbage_bytes;
      } else {
        candidate_.push_back(byte);
      }
      return;

    case State::comment:
      if (is_line_end(byte)) {
        ++stats_.comment_lines;
        state_ = State::between;
        at_line_start_ = true;
      } else if (is_printable(byte) || byte == '\t') {
        ++comment_chars_;
      } else {  // binary after a '#': it was never a comment
        stats_.garbage_bytes += comment_chars_;
        state_ = State::between;
        at_line_start_ = false;
        ++stats_.garbage_bytes;
      }
      return;

    case State::rest_of_line:
      if (is_line_end(byte)) {
        state_ = State::between;
        at_line_start_ = true;
      } else if (byte == '$') {
        start_sentence();
      } else {
        ++stats_.garbage_bytes;
      }
      return;

    case State::between:
      if (byte == '$') {
        start_sentence();
      } else if (is_line_end(byte)) {
        at_line_start_ = true;
      } else if (byte == '#' && at_line_start_) {
        state_ = State::comment;
        comment_chars_ = 1;
      } else {
        ++stats_.garbage_bytes;
        at_line_start_ = false;
      }
      return;
  }
}

void StreamReader::start_sentence() {
  candidate_.assign(1, '$');
  state_ = State::sentence;
  at_line_start_ = false;
}

void StreamReader::end_sentence(std::vector<Sentence>& out) {
  Result<Sentence> parsed = parse_sentence(candidate_);
  candidate_.clear();
  if (parsed.ok()) {
    ++stats_.sentences_ok;
    out.push_back(std::move(parsed).value());
  } else if (parsed.error() == ParseError::bad_checksum) {
    ++stats_.bad_checksum;
  } else {
    ++stats_.malformed;
  }
}

void StreamReader::abandon_sentence() {
  if (candidate_.find_first_of(",*") == std::string::npos) {
    stats_.garbage_bytes += candidate_.size();  // a stray '$' in binary data
  } else {
    ++stats_.malformed;  // a sentence cut short
  }
  candidate_.clear();
}

}  // namespace gpsemu::nmea
