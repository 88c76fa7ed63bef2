#include <fmt/format.h>

#include "nmea/sentences.hpp"

namespace gpsemu::nmea {

unsigned char checksum(std::string_view body) {
  unsigned char sum = 0;
  for (const char c : body) sum ^= static_cast<unsigned char>(c);
  return sum;
}

std::string frame(std::string_view body) {
  return fmt::format("${}*{:02X}\r\n", body, checksum(body));
}

}  // namespace gpsemu::nmea
