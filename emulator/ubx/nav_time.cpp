// GPS time and NAV-TIMELS (see nav.hpp). Layout: u-blox's interface descriptions (M8 protocol 18, F9 HPG 1.32).
#include <algorithm>
#include <chrono>
#include <cstdint>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/nav.hpp"

namespace gpsemu::ubx {
namespace {

constexpr std::uint32_t kSourceGps = 2;            // srcOfCurrLs / srcOfLsChange: GPS
constexpr std::uint32_t kSourceUnknown = 255;      // srcOfCurrLs before UTC is known
constexpr std::uint32_t kLastLeapSecondWeek = 1929;  // the leap second at the end of 2016-12-31 (Saturday)
constexpr std::uint32_t kLastLeapSecondDay = 7;      // day of week, Sunday 1

}  // namespace

GpsTime gps_time(nmea::UtcTime utc, int gps_minus_utc_s) {
  using namespace std::chrono;
  constexpr sys_days gps_epoch{year{1980} / January / 6};
  const milliseconds since = utc - time_point_cast<milliseconds>(gps_epoch) + seconds{gps_minus_utc_s};
  constexpr milliseconds week = duration_cast<milliseconds>(weeks{1});
  const auto w = since / week;
  return {static_cast<int>(w), static_cast<std::uint32_t>((since - w * week).count())};
}

std::string nav_timels(const nmea::Fix& fix, const NavExtras& extras) {
  using namespace std::chrono;
  const bool known = extras.time.valid && extras.time.resolved;
  const nmea::LeapSeconds& leap = fix.leap;
  std::uint32_t week = kLastLeapSecondWeek, day = kLastLeapSecondDay;
  if (leap.event_day) {
    // The GPS week and day (Sunday 1) of the UTC day the leap second ends (ICD-GPS-200 WN_LSF, DN).
    constexpr sys_days gps_epoch{year{1980} / January / 6};
    const auto since = (*leap.event_day - gps_epoch).count();
    week = static_cast<std::uint32_t>(since / 7);
    day = static_cast<std::uint32_t>(since % 7 + 1);
  }
  std::string p;
  put_u4(p, gps_time(fix).tow_ms);
  put_u1(p, 0);  // version
  put_zeros(p, 3);
  put_u1(p, known ? kSourceGps : kSourceUnknown);
  put_i1(p, leap.gps_minus_utc_s);  // currLs: the firmware's default until it is known
  put_u1(p, known ? kSourceGps : 0);
  put_i1(p, known ? leap.change_s : 0);  // lsChange: +1 / -1 announced, 0 none
  // timeToLsEvent (s), held within its 32 bits for an event centuries away
  const std::int64_t to_event_s = std::clamp<std::int64_t>(leap.time_to_event_s, INT32_MIN, INT32_MAX);
  put_i4(p, known && leap.event_day ? static_cast<std::int32_t>(to_event_s) : 0);
  put_u2(p, known ? week : 0);
  put_u2(p, known ? day : 0);
  put_zeros(p, 3);
  put_u1(p, known ? 0x03u : 0u);  // valid: validCurrLs, validTimeToLsEvent
  return p;
}

}  // namespace gpsemu::ubx
