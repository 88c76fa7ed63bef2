// True heading sentences of a dual-antenna (moving-base) receiver: HDT and THS, formatted from a
// Fix's heading and parsed back. Pure: values in, text out (and back).
//
//   $GPHDT,123.45,T*hh     heading (degrees true, 2 decimals, [0, 360)); no heading: $GPHDT,,T*hh
//   $GPTHS,123.45,A*hh     heading and mode: A autonomous, V not valid; no heading: $GPTHS,,V*hh
//
// Readers: ArduPilot's AP_GPS_NMEA takes the heading of either (hundredths of a degree) and, for
// THS, only with mode A (V clears its GPS yaw); an empty HDT field leaves its last yaw in place,
// so for ArduPilot THS is the sentence that can say "no heading". gpsd decodes both (ATT heading).
#pragma once

#include <optional>
#include <string>

#include "nmea/fix.hpp"
#include "nmea/parse.hpp"

namespace gpsemu::nmea {

/// HDT: the fix's heading_deg_true, empty when unknown (also without a position fix: a heading
/// needs both antennas' solutions).
[[nodiscard]] std::string format_hdt(const Fix& fix, const FormatOptions& options);

/// THS: the heading and mode A, or an empty heading and mode V when there is none.
[[nodiscard]] std::string format_ths(const Fix& fix, const FormatOptions& options);

/// The heading a Fix carries as HDT/THS write it: empty without a position fix or a heading.
[[nodiscard]] std::optional<double> reported_heading_deg(const Fix& fix);

/// A parsed HDT or THS: the heading (empty field: nullopt) and THS's mode ('T' for HDT's unit).
struct HeadingSentence {
  std::optional<double> heading_deg_true;
  char mode = 'V';  ///< THS: A E M S V; HDT: its unit field, 'T'
};

/// Reads an HDT (any talker): 2 fields, unit 'T'. wrong_type for another sentence.
[[nodiscard]] Result<HeadingSentence> parse_hdt(const Sentence& sentence);
/// Reads a THS (any talker): 2 fields, mode one of A E M S V.
[[nodiscard]] Result<HeadingSentence> parse_ths(const Sentence& sentence);

}  // namespace gpsemu::nmea
