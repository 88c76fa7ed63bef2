// gpsemu ctl's words as one control request (control.hpp's JSON line), pure. Every parameter of
// every fault kind has a flag, made from the catalogue (catalogue.hpp): --KEY with dashes
// (--speed-mps) and, when the key names a unit, the same without it (--speed); --FLAG VALUE or
// --FLAG=VALUE; a true/false parameter alone means true (--detected). Beside its own parameters a
// live fault takes --duration, --where and --receiver.
//   KIND [--FLAG VALUE]...      {"fault":KIND,...}
//   clear KIND [--receiver N]   {"clear":KIND,...}
//   status                      {"status":true}
//   send JSON                   JSON as it is
#pragma once

#include <string>
#include <vector>

namespace gpsemu::faults {

/// The request line of gpsemu ctl's words after PATH. Throws std::invalid_argument naming what is
/// wrong (an unknown kind or flag, a flag without a value, a word too many).
[[nodiscard]] std::string control_request_of(const std::vector<std::string>& words);

/// The help's list of the kinds and their flags, one line a kind ("  jam: --db, --ramp-out-s|--ramp-out,
/// ..."), then each parameter's unit and range from the catalogue ("  --db: C/N0 drop ..., dB, 0..60").
[[nodiscard]] std::string control_flags_help();

}  // namespace gpsemu::faults
