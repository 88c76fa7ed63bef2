// --ui [HOST:]PORT: where the bench view listens (emulator/ui/http_server.hpp), parsed where the
// configuration is read so a bad value stops the start-up with one message.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace gpsemu::ui {

struct HttpSettings {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;            ///< 0: the system picks one (logged)
  std::optional<std::string> token;  ///< --ui-token; a non-loopback bind without one gets a random one
};

/// "[HOST:]PORT" (HOST default 127.0.0.1); throws std::invalid_argument naming what was wrong.
[[nodiscard]] HttpSettings parse_ui_spec(const std::string& spec);
/// Whether `host` is a loopback address (127.0.0.0/8, ::1, localhost).
[[nodiscard]] bool is_loopback(const std::string& host);

}  // namespace gpsemu::ui
