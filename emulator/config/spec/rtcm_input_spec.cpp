#include "emulator/config/spec/rtcm_input_spec.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace gpsemu::transport {

RtcmInputSpec parse_rtcm_input_spec(std::string_view text) {
  RtcmInputSpec spec;
  if (text.starts_with("tcp:")) {
    spec.tcp = true;
  } else if (text.starts_with("udp:")) {
    spec.tcp = false;
  } else {
    throw std::invalid_argument(fmt::format("expected tcp:[HOST:]PORT or udp:[HOST:]PORT, got '{}'", text));
  }
  spec.endpoint = posix::parse_endpoint(text.substr(4));
  return spec;
}

}  // namespace gpsemu::transport
