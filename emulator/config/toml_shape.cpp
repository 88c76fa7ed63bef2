#include "emulator/config/toml_shape.hpp"

#include <cctype>

#include <fmt/format.h>

#include "emulator/config/config.hpp"

namespace gpsemu {

void check_toml_shape(std::string_view text, std::string_view what, const std::string& name) {
  std::size_t line = 1, parts = 1, depth = 0;
  const auto fail = [&](const std::string& why) {
    throw ConfigError(fmt::format("{} {}:{}: {}", what, name, line, why));
  };
  // Skips a string starting at `at` (its quote) and returns the index of its closing quote.
  const auto skip_string = [&](std::size_t at) {
    const char quote = text[at];
    const bool multi = text.substr(at, 3) == std::string_view(quote == '"' ? "\"\"\"" : "'''");
    const std::string_view close = multi ? text.substr(at, 3) : text.substr(at, 1);
    std::size_t k = at + close.size();
    while (k < text.size() && text.substr(k, close.size()) != close) {
      if (text[k] == '\n') {
        if (!multi) return k;  // an unterminated one-line string: the parser's to report
        ++line;
      }
      if (quote == '"' && text[k] == '\\') ++k;
      ++k;
    }
    return k + close.size() - 1;
  };
  for (std::size_t at = 0; at < text.size(); ++at) {
    const char c = text[at];
    if (c == '"' || c == '\'') {
      at = skip_string(at);  // a quoted key part: the dotted run goes on
      continue;
    }
    if (c == '#') {
      while (at + 1 < text.size() && text[at + 1] != '\n') ++at;
      continue;
    }
    if (c == '.') {
      if (++parts > kMaxTomlKeyParts) fail(fmt::format("a key of more than {} dotted parts", kMaxTomlKeyParts));
      continue;
    }
    if (c == '{' || (c == '[' && depth > 0)) {
      if (++depth > kMaxTomlNesting) fail(fmt::format("values nested deeper than {} levels", kMaxTomlNesting));
    } else if (c == '[' && depth == 0) {
      // A table header ([a.b], [[fault]]) or an array value: an array after '=' nests.
      std::size_t k = at;
      while (k > 0 && (text[k - 1] == ' ' || text[k - 1] == '\t')) --k;
      if (k > 0 && text[k - 1] == '=' && ++depth > kMaxTomlNesting) fail("values nested too deep");
    } else if ((c == '}' || c == ']') && depth > 0) {
      --depth;
    }
    if (c == '\n') ++line;
    const bool in_key = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == ' ' || c == '\t';
    if (!in_key) parts = 1;
  }
}

}  // namespace gpsemu
