// Formatting of NMEA 0183 sentences from a Fix: one pure function per sentence type.
// Every function returns one complete sentence: "$" talker type "," fields "*hh" CR LF.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

#include "nmea/fix.hpp"
#include "nmea/sentence_set.hpp"

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
/// satellites two digits (clamped 0..99), HDOP 2 decimals (clamped to 99.99), altitude
/// options.alt_decimals decimals (default 1), separation 1 decimal. No fix: $GPGGA,hhmmss.ss,,,,,0,00,99.99,,,,,,*hh (time still present).
[[nodiscard]] std::string format_gga(const Fix& fix, const FormatOptions& options);

/// GGA in a 2-D fix (fix.dimension == two_d): altitude and geoid separation are left empty, as
/// receivers do, so consumers (gpsd) report mode 2.
///
/// RMC: time, status A/V, position, speed (knots), course (degrees true), date, mode (2.3+),
/// navigational status (4.1):
///   $GPRMC,hhmmss.ss,A,ddmm.mmmmm,N,dddmm.mmmmm,E,k.kkk,c.cc,ddmmyy,,,A[,V]*hh
/// speed 3 decimals of knots, course 2 decimals in [0, 360) or empty when unknown, magnetic
/// variation empty, mode from mode_indicator(), 4.1 navigational status always "V" (as u-blox).
/// Status is "A" for every fix quality but none. No fix: status V, position, speed and course
/// empty, mode N, time and date still present.
[[nodiscard]] std::string format_rmc(const Fix& fix, const FormatOptions& options);

/// VTG: course over ground (degrees true), magnetic course (empty), speed in knots and km/h, mode
/// indicator (u-blox style; every supported NMEA version has it):
///   $GPVTG,c.cc,T,,M,k.kkk,N,k.kkk,K,A*hh
/// course as in RMC (empty when unknown), speeds 3 decimals. No fix: $GPVTG,,T,,M,,N,,K,N*hh.
[[nodiscard]] std::string format_vtg(const Fix& fix, const FormatOptions& options);

/// GLL: position, time, status, mode indicator:
///   $GPGLL,ddmm.mmmmm,N,dddmm.mmmmm,E,hhmmss.ss,A,A*hh
/// No fix: $GPGLL,,,,,hhmmss.ss,V,N*hh (time still present, as u-blox).
[[nodiscard]] std::string format_gll(const Fix& fix, const FormatOptions& options);

/// ZDA: UTC time and date, local zone hours and minutes (always 00,00):
///   $GPZDA,hhmmss.ss,dd,mm,yyyy,00,00*hh
/// Written with or without a fix: the receiver's clock is always set here.
[[nodiscard]] std::string format_zda(const Fix& fix, const FormatOptions& options);

/// GST: pseudorange error statistics, all 1-sigma in metres:
///   $GPGST,hhmmss.ss,rms,major,minor,orient,lat,lon,alt*hh
/// rms = fix.range_rms_m; lat/lon/alt = fix.sigma_lat_m/sigma_lon_m/sigma_alt_m; the error
/// ellipse of independent north and east errors: major = max(lat, lon), minor = min(lat, lon),
/// orientation of the major axis 0.0 (north) when lat >= lon, else 90.0 degrees true. Metres with
/// 3 decimals (RTK errors are millimetres), orientation 1 decimal; a value that does not fit
/// (>= 1000 m) is empty. No fix: $GPGST,hhmmss.ss,,,,,,,*hh.
[[nodiscard]] std::string format_gst(const Fix& fix, const FormatOptions& options);

/// GSA: mode A (automatic), fix type 1/2/3, the PRNs of the satellites used (12 slots per
/// sentence), PDOP, HDOP, VDOP with 2 decimals (capped at 99.99); NMEA 4.1 adds the system ID (1,
/// GPS). More than 12 satellites used give several GSA sentences (u-blox does so per
/// constellation), each with the same fix type and DOPs:
///   $GPGSA,A,3,02,05,...,,,1.61,0.88,1.35,1*hh
/// No fix: $GPGSA,A,1,,,,,,,,,,,,,99.99,99.99,99.99,1*hh. Talker: options.talker.
[[nodiscard]] std::string format_gsa(const Fix& fix, const FormatOptions& options);
/// format_gsa appended to `out`.
void append_gsa(const Fix& fix, const FormatOptions& options, std::string& out);

/// GSV: satellites in view, 4 per sentence, as many sentences as needed (up to 8 for 32):
///   $GPGSV,total,number,in_view,prn,elev,azim,snr,...[,1]*hh
/// PRN 2 digits, elevation 2 digits, azimuth 3 digits, SNR 2 digits (empty when not tracked); the
/// last sentence carries only the satellites left (no empty padding, as u-blox). NMEA 4.1 adds the
/// signal ID (1, GPS L1 C/A). None in view: $GPGSV,1,1,00[,1]*hh. The satellites are GPS, so the
/// talker is GP when options.talker is GN (u-blox writes GSV per constellation), else options.talker.
[[nodiscard]] std::string format_gsv(const Fix& fix, const FormatOptions& options);
/// format_gsv appended to `out`.
void append_gsv(const Fix& fix, const FormatOptions& options, std::string& out);

/// Every sentence of `type` for one epoch (GSA and GSV may be several).
[[nodiscard]] std::string format_sentences(SentenceType type, const Fix& fix, const FormatOptions& options);

/// Appends every sentence type in options.sentences, in receiver order, to `out` (not cleared).
void append_epoch(const Fix& fix, const FormatOptions& options, std::string& out);

/// The GSA and GSV text of an earlier epoch and what it was made from. A caller that keeps one per
/// stream (with the same FormatOptions) passes it to append_epoch, which reuses the text while the
/// satellites (and, for GSA, the fix state and DOPs) are unchanged: the sky's integer degrees
/// change every few seconds, and GSA/GSV are most of an epoch's bytes. Plain data, no hidden state.
struct SatelliteTextMemo {
  bool gsv_valid = false, gsa_valid = false;
  int in_view = 0;
  std::array<SatelliteInView, max_satellites> satellites{};
  FixQuality quality = FixQuality::none;
  FixDimension dimension = FixDimension::none;
  double pdop = 0.0, hdop = 0.0, vdop = 0.0;
  std::string gsa, gsv;
};
/// append_epoch, reusing and updating `memo` (same output bytes).
void append_epoch(const Fix& fix, const FormatOptions& options, std::string& out, SatelliteTextMemo& memo);

}  // namespace gpsemu::nmea
