// GPS time of a receiver's epoch: week and time of week from UTC and the leap seconds the receiver
// knows. A fact below every protocol (UBX iTOW, RTCM3 MSM epoch times, the next receiver families'
// week/TOW fields all read it); in the small pure library gpsemu_facts.
#pragma once

#include <cstdint>

#include "nmea/fix.hpp"

namespace gpsemu {

/// GPS time minus UTC since 2017-01-01 (seconds): a receiver's default until a new leap second.
inline constexpr int kGpsMinusUtcDefaultS = 18;

/// GPS week and time of week.
struct GpsTime {
  int week = 0;              ///< weeks since 1980-01-06
  std::uint32_t tow_ms = 0;  ///< milliseconds into the week
};
/// GPS week and time of week of UTC time `utc`, GPS being `gps_minus_utc_s` ahead of UTC.
[[nodiscard]] GpsTime gps_time(nmea::UtcTime utc, int gps_minus_utc_s = kGpsMinusUtcDefaultS);
/// The same of a fix's time, with the leap seconds it reports (fix.leap).
[[nodiscard]] inline GpsTime gps_time(const nmea::Fix& fix) { return gps_time(fix.time_utc, fix.leap.gps_minus_utc_s); }

}  // namespace gpsemu
