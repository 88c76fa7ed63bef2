#include "emulator/faults/json_shape.hpp"

#include <unordered_set>
#include <vector>

#include <fmt/format.h>

namespace gpsemu::faults {

std::optional<std::string> json_shape_problem(std::string_view text, std::size_t max_depth) {
  struct Level {
    bool object = false;
    bool expecting_key = false;
    std::unordered_set<std::string_view> keys;
  };
  std::vector<Level> levels;
  for (std::size_t at = 0; at < text.size(); ++at) {
    const char c = text[at];
    if (c == '"') {
      const std::size_t begin = at + 1;
      for (++at; at < text.size() && text[at] != '"'; ++at) {
        if (text[at] == '\\') ++at;  // the escaped character, whatever it is
      }
      if (at >= text.size()) return std::nullopt;  // an unterminated string: the parser's to report
      if (!levels.empty() && levels.back().object && levels.back().expecting_key) {
        const std::string_view key = text.substr(begin, at - begin);
        if (!levels.back().keys.insert(key).second) {
          return fmt::format("key \"{}\" given twice in one object", key.substr(0, 64));
        }
        levels.back().expecting_key = false;
      }
    } else if (c == '{' || c == '[') {
      if (levels.size() >= max_depth) return fmt::format("nested deeper than {} levels", max_depth);
      levels.push_back({c == '{', c == '{', {}});
    } else if (c == '}' || c == ']') {
      if (levels.empty()) return std::nullopt;  // unbalanced: the parser's to report
      levels.pop_back();
    } else if (c == ',' && !levels.empty() && levels.back().object) {
      levels.back().expecting_key = true;
    }
  }
  return std::nullopt;
}

}  // namespace gpsemu::faults
