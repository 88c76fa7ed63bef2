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

/// NMEA 2.3+ mode indicator (RMC, GLL, VTG) for a fix quality: N none, A autonomous, D
/// differential, P precise (PPS), R RTK fixed, F RTK float, E estimated (dead reckoning).
[[nodiscard]] char mode_indicator(FixQuality quality);

/// GGA: time, position, quality, satellites, HDOP, MSL altitude, geoid separation (u-blox style):
///   $GPGGA,hhmmss.ss,ddmm.mmmmm,N,dddmm.mmmmm,E,q,ss,h.hh,a.a,M,g.g,M,,*hh
/// satellites two digits (clamped 0..99), HDOP 2 decimals (clamped to 99.99), altitude and
/// separation 1 decimal. No fix: $GPGGA,hhmmss.ss,,,,,0,00,99.99,,,,,,*hh (time still present).
[[nodiscard]] std::string format_gga(const Fix& fix, const FormatOptions& options);

/// RMC: time, status A/V, position, speed (knots), course (degrees true), date, mode (2.3+),
/// navigational status (4.1):
///   $GPRMC,hhmmss.ss,A,ddmm.mmmmm,N,dddmm.mmmmm,E,k.kkk,c.cc,ddmmyy,,,A[,V]*hh
/// speed 3 decimals of knots, course 2 decimals in [0, 360) or empty when unknown, magnetic
/// variation empty, mode from mode_indicator(), 4.1 navigational status always "V" (as u-blox).
/// Status is "A" for every fix quality but none. No fix: status V, position, speed and course
/// empty, mode N, time and date still present.
[[nodiscard]] std::string format_rmc(const Fix& fix, const FormatOptions& options);

}  // namespace gpsemu::nmea
