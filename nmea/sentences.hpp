// Formatting of NMEA 0183 sentences from a Fix: one pure function per sentence type.
// Every function returns one complete sentence: "$" talker type "," fields "*hh" CR LF.
#pragma once

#include <string>
#include <string_view>

#include "nmea/fix.hpp"

namespace gpsemu::nmea {

/// XOR of the bytes between '$' and '*' (exclusive) of `body` (the text after '$', before '*').
[[nodiscard]] unsigned char checksum(std::string_view body);

/// Wraps a body ("GPGGA,...") into "$body*hh\r\n".
[[nodiscard]] std::string frame(std::string_view body);

/// GGA: time, position, quality, satellites, HDOP, MSL altitude, geoid separation.
[[nodiscard]] std::string format_gga(const Fix& fix, const FormatOptions& options);

/// RMC: time, status A/V, position, speed (knots), course (degrees true), date, mode (2.3+),
/// navigational status (4.1).
[[nodiscard]] std::string format_rmc(const Fix& fix, const FormatOptions& options);

}  // namespace gpsemu::nmea
