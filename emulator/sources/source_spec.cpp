#include "emulator/sources/source_spec.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::sources {

SourceSpec parse_source_spec(std::string_view text) {
  SourceSpec spec;
  spec.text = std::string(text);
  const auto starts = [text](std::string_view prefix) { return text.substr(0, prefix.size()) == prefix; };
  if (starts("sim:")) {
    spec.kind = SourceKind::sim;
    spec.scenario = std::string(text.substr(4));
    return spec;
  }
  if (starts("replay:")) {
    spec.kind = SourceKind::replay;
    spec.path = std::string(text.substr(7));
    return spec;
  }
  if (starts("udp:") || starts("tcp:")) {
    spec.kind = starts("udp:") ? SourceKind::udp : SourceKind::tcp;
    try {
      spec.endpoint = transport::parse_pose_endpoint(text.substr(4));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("--source {}: {}", text, e.what()));
    }
    return spec;
  }
  if (starts("mavlink:")) {
    const std::string_view rest = text.substr(8);
    const bool udp = rest.substr(0, 4) == "udp:";
    if (!udp && rest.substr(0, 4) != "tcp:") {
      throw std::invalid_argument(fmt::format("--source {}: a MAVLink source is mavlink:udp:[HOST:]PORT (listen) or "
                                              "mavlink:tcp:HOST:PORT (connect)", text));
    }
    spec.kind = udp ? SourceKind::mavlink_udp : SourceKind::mavlink_tcp;
    try {
      spec.endpoint = transport::parse_pose_endpoint(rest.substr(4));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("--source {}: {}", text, e.what()));
    }
    if (!udp && spec.endpoint.port == 0) {
      throw std::invalid_argument(fmt::format("--source {}: mavlink:tcp connects to a port: give one from 1 to 65535", text));
    }
    return spec;
  }
  throw std::invalid_argument(fmt::format("unknown pose source '{}' (accepted: {})", text, kSourceSpecForms));
}

}  // namespace gpsemu::sources
