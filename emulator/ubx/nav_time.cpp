// NAV-TIMELS (see nav.hpp). Layout: u-blox's interface descriptions (M8 protocol 18, F9 HPG 1.32).
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/nav.hpp"

namespace gpsemu::ubx {
namespace {

constexpr std::uint32_t kSourceGps = 2;            // srcOfCurrLs / srcOfLsChange: GPS
constexpr std::uint32_t kSourceUnknown = 255;      // srcOfCurrLs before UTC is known
constexpr std::uint32_t kLastLeapSecondWeek = 1929;  // the leap second at the end of 2016-12-31 (Saturday)
constexpr std::uint32_t kLastLeapSecondDay = 7;      // day of week, Sunday 1

}  // namespace

std::string nav_timels(const nmea::Fix& fix, const NavExtras& extras) {
  const bool known = extras.time.valid && extras.time.resolved;
  std::string p;
  put_u4(p, gps_time(fix.time_utc).tow_ms);
  put_u1(p, 0);  // version
  put_zeros(p, 3);
  put_u1(p, known ? kSourceGps : kSourceUnknown);
  put_i1(p, gps_leap_seconds);  // currLs: the firmware's default until it is known
  put_u1(p, known ? kSourceGps : 0);
  put_i1(p, 0);  // lsChange: none announced
  put_i4(p, 0);  // timeToLsEvent (s)
  put_u2(p, known ? kLastLeapSecondWeek : 0);
  put_u2(p, known ? kLastLeapSecondDay : 0);
  put_zeros(p, 3);
  put_u1(p, known ? 0x03u : 0u);  // valid: validCurrLs, validTimeToLsEvent
  return p;
}

}  // namespace gpsemu::ubx
