// The control socket as a user names it (--control unix:PATH | tcp:[HOST:]PORT): checked and
// written in its canonical form. The pipeline listens on it (emulator/pipeline/control_socket.hpp).
#pragma once

#include <string>

namespace gpsemu {

/// "unix:PATH" -> PATH; "tcp:[HOST:]PORT" -> "tcp:HOST:PORT" (HOST default 127.0.0.1; port 0: the
/// system picks one, logged at start-up); throws std::invalid_argument otherwise.
[[nodiscard]] std::string parse_control_spec(const std::string& spec);

}  // namespace gpsemu
