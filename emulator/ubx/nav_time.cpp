// NAV-TIMELS (see nav.hpp; GPS time itself: model/gps_time.hpp). Layout: u-blox's interface descriptions (M8 protocol 18, F9 HPG 1.32).
#include <algorithm>
#include <chrono>
#include <cstdint>

#include "emulator/ubx/layouts.hpp"
#include "emulator/ubx/nav.hpp"

namespace gpsemu::ubx {
namespace {

constexpr std::uint32_t kSourceGps = 2;            // srcOfCurrLs / srcOfLsChange: GPS
constexpr std::uint32_t kSourceUnknown = 255;      // srcOfCurrLs before UTC is known
constexpr std::uint32_t kLastLeapSecondWeek = 1929;  // the leap second at the end of 2016-12-31 (Saturday)
constexpr std::uint32_t kLastLeapSecondDay = 7;      // day of week, Sunday 1

}  // namespace

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
  PayloadWriter<layout::nav_timels> w;
  w.set<"iTOW">(gps_time(fix).tow_ms);
  w.set<"version">(0);
  w.set<"srcOfCurrLs">(known ? kSourceGps : kSourceUnknown);
  w.set<"currLs">(leap.gps_minus_utc_s);  // the firmware's default until it is known
  w.set<"srcOfLsChange">(known ? kSourceGps : 0);
  w.set<"lsChange">(known ? leap.change_s : 0);  // +1 / -1 announced, 0 none
  // timeToLsEvent (s), held within its 32 bits for an event centuries away
  const std::int64_t to_event_s = std::clamp<std::int64_t>(leap.time_to_event_s, INT32_MIN, INT32_MAX);
  w.set<"timeToLsEvent">(known && leap.event_day ? static_cast<std::int32_t>(to_event_s) : 0);
  w.set<"dateOfLsGpsWn">(known ? week : 0);
  w.set<"dateOfLsGpsDn">(known ? day : 0);
  w.set<"valid">(known ? 0x03u : 0u);  // validCurrLs, validTimeToLsEvent
  return std::move(w).bytes();
}

}  // namespace gpsemu::ubx
