// The bench view's page and its assets (emulator/ui/page/), embedded in the binary at build time
// (emulator/ui/embed_assets.cmake): nothing is fetched from anywhere else.
#pragma once

#include <string_view>
#include <vector>

namespace gpsemu::ui {

struct Asset {
  std::string_view path;          ///< "/", "/app.js", ...
  std::string_view content_type;  ///< "text/html; charset=utf-8", ...
  std::string_view body;
};

[[nodiscard]] const std::vector<Asset>& assets();

}  // namespace gpsemu::ui
