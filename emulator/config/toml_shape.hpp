// A TOML text's shape checked before toml++ parses it: no key or table header of more than
// kMaxTomlKeyParts dotted parts ([a.a.a...] of 50 000 parts crashed the parser's recursion), no
// arrays or inline tables nested deeper than kMaxTomlNesting. Pure: text in, a ConfigError out
// naming the source and the line.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace gpsemu {

/// More parts than any key of ours has ([[fault]] area.polygon is 2; receiver.ubx.messages 3).
inline constexpr std::size_t kMaxTomlKeyParts = 16;
inline constexpr std::size_t kMaxTomlNesting = 16;

/// Throws ConfigError "WHAT NAME:LINE: ..." when `text` has a key of too many parts or values
/// nested too deep; otherwise leaves the text to the parser (which reports what is malformed).
void check_toml_shape(std::string_view text, std::string_view what, const std::string& name);

}  // namespace gpsemu
