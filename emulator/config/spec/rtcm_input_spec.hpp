// An RTCM3 input as a user writes it (--rtcm tcp:[HOST:]PORT | udp:[HOST:]PORT): the value and its
// parser. The transport opens it (transport/input/rtcm_socket.hpp).
#pragma once

#include <string_view>

#include "emulator/config/spec/endpoint.hpp"

namespace gpsemu::transport {

struct RtcmInputSpec {
  bool tcp = true;
  posix::Endpoint endpoint;
};

/// Parses "tcp:[HOST:]PORT" or "udp:[HOST:]PORT". Throws std::invalid_argument naming the text.
[[nodiscard]] RtcmInputSpec parse_rtcm_input_spec(std::string_view text);

}  // namespace gpsemu::transport
