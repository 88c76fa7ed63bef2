// Test support: split received bytes into NMEA sentences and check each one's frame and checksum,
// so a test can assert that only whole, valid sentences (and whole epochs) arrived; and build
// checksummed test sentences and epochs to write.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace gpsemu::test {

/// True when `line` (without CR LF) is `$BODY*hh` with the right checksum.
inline bool valid_sentence(const std::string& line) {
  if (line.size() < 4 || line[0] != '$') return false;
  const auto star = line.rfind('*');
  if (star == std::string::npos || star + 3 != line.size()) return false;
  unsigned sum = 0;
  for (std::size_t i = 1; i < star; ++i) sum ^= static_cast<unsigned char>(line[i]);
  char hex[3];
  std::snprintf(hex, sizeof hex, "%02X", sum);
  return line.compare(star + 1, 2, hex) == 0;
}

struct SplitResult {
  std::vector<std::string> sentences;  ///< whole lines, without CR LF
  std::size_t invalid = 0;             ///< lines that are not valid sentences
  std::string rest;                    ///< bytes after the last CR LF (a partial sentence)
};

/// Splits `text` at CR LF and checks every line.
inline SplitResult split_sentences(const std::string& text) {
  SplitResult r;
  std::size_t pos = 0;
  for (;;) {
    const auto end = text.find("\r\n", pos);
    if (end == std::string::npos) break;
    std::string line = text.substr(pos, end - pos);
    if (!valid_sentence(line)) ++r.invalid;
    r.sentences.push_back(std::move(line));
    pos = end + 2;
  }
  r.rest = text.substr(pos);
  return r;
}

/// "$BODY*hh" + CR LF with the right checksum.
inline std::string sentence(const std::string& body) {
  unsigned sum = 0;
  for (const char c : body) sum ^= static_cast<unsigned char>(c);
  char tail[8];
  std::snprintf(tail, sizeof tail, "*%02X\r\n", sum);
  return "$" + body + tail;
}

/// One 10 Hz test epoch (GGA + RMC, about 140 bytes) whose time field is 12:00:00.0 + k/10 s.
inline std::string epoch(int k) {
  char time[16];
  std::snprintf(time, sizeof time, "12%02d%02d.%d0", (k / 600) % 60, (k / 10) % 60, k % 10);
  const std::string t = time;
  return sentence("GPGGA," + t + ",4717.11399,N,00833.91590,E,1,08,0.9,545.4,M,46.9,M,,") +
         sentence("GPRMC," + t + ",A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A");
}

/// The sentence type after the talker: "GGA" for "$GPGGA,...".
inline std::string sentence_type(const std::string& s) { return s.size() >= 6 ? s.substr(3, 3) : std::string(); }

/// The time field (field 1) of a GGA or RMC sentence: "120000.10".
inline std::string time_field(const std::string& s) {
  const auto a = s.find(',');
  if (a == std::string::npos) return {};
  const auto b = s.find(',', a + 1);
  return s.substr(a + 1, b == std::string::npos ? std::string::npos : b - a - 1);
}

/// Seconds of the UTC day of a time field "hhmmss.ss".
inline double seconds_of_day(const std::string& hhmmss) {
  return std::stoi(hhmmss.substr(0, 2)) * 3600.0 + std::stoi(hhmmss.substr(2, 2)) * 60.0 + std::stod(hhmmss.substr(4));
}

/// A whole sentence (without CR LF) and when the chunk that completed it was read.
struct ReadSentence {
  double read_s;  ///< CLOCK_REALTIME, seconds (Process::chunks())
  std::string text;
};

/// Every whole sentence of a stream read in chunks (Process::chunks(): bytes and read times), in order.
template <class Chunks>
std::vector<ReadSentence> sentences_as_read(const Chunks& chunks) {
  std::vector<ReadSentence> out;
  std::string pending;
  for (const auto& chunk : chunks) {
    pending += chunk.bytes;
    SplitResult split = split_sentences(pending);
    pending = std::move(split.rest);
    for (std::string& s : split.sentences) out.push_back({chunk.read_s, std::move(s)});
  }
  return out;
}

}  // namespace gpsemu::test
