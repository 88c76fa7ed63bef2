// A JSON request's shape checked before it is parsed: nesting no deeper than a limit and no key
// twice in one object. Every JSON text that reaches gpsemu from a client (control socket lines,
// the bench view's fault requests) passes here first, so a request of 80 000 nested brackets is
// refused in one pass over its bytes instead of recursing through a parser, a printer or our own
// handlers, and {"fault":"jam","fault":"outage"} is an error rather than the last key winning.
// Pure: text in, an error message or nothing out.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace gpsemu::faults {

/// Deepest nesting of objects and arrays a control request may have ({"fault":...,"area":[[..]]} is 3).
inline constexpr std::size_t kMaxJsonDepth = 16;

/// Why `text` is refused before parsing ("nested deeper than 16 levels", "key \"fault\" given
/// twice"), or nothing when its shape is fine. Malformed JSON is left to the parser (nothing).
[[nodiscard]] std::optional<std::string> json_shape_problem(std::string_view text, std::size_t max_depth = kMaxJsonDepth);

}  // namespace gpsemu::faults
