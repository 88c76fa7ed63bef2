#include <fmt/format.h>

#include "nmea/sentences.hpp"
#include "nmea/text_append.hpp"

namespace gpsemu::nmea {

unsigned char checksum(std::string_view body) {
  unsigned char sum = 0;
  for (const char c : body) sum ^= static_cast<unsigned char>(c);
  return sum;
}

std::string frame(std::string_view body) {
  std::string sentence;
  sentence.reserve(body.size() + 6);
  sentence += '$';
  sentence += body;
  text::close_sentence(sentence);
  return sentence;
}

}  // namespace gpsemu::nmea
