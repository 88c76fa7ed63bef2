// A `time` fault with mode = "leap-second" on a fix and in the UBX messages: announced from the
// fault's start (NAV-TIMELS lsChange +1, timeToLsEvent counting down), 23:59:60 for one second
// (Fix::leap.in_second_60, NAV-PVT and NAV-TIMEUTC sec 60, the date still the old day), then UTC
// one second behind with GPS - UTC 19 (NAV-TIMEGPS leapS, NAV-TIMELS currLs); GPS time (iTOW)
// runs on without a step. And its keys refused with the reason.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "emulator/faults/fault_timeline.hpp"
#include "emulator/faults/sky_faults.hpp"
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/nav.hpp"
#include "tests/support/fault_fixes.hpp"

namespace gpsemu::faults {
namespace {
namespace leap_second_test {

using namespace std::chrono;

const Geodetic kOrigin{47.0, 8.0, 400.0};
/// The receiver's clock (UTC as counted before the leap second): three seconds before the event.
const UtcNs kStart = parse_iso8601_utc("2026-12-31T23:59:57Z");
const nmea::UtcTime kEvent{sys_days{year{2027} / January / 1}};

Fault leap_fault(double at_s = 0.0) {
  return make_fault({{"kind", std::string("time")}, {"mode", std::string("leap-second")},
                     {"leap_utc", std::string("2026-12-31T23:59:60Z")}, {"at", at_s}});
}

struct Epochs {
  explicit Epochs(Fault f) : frame(kOrigin), timeline(FaultPlan{{std::move(f)}, ""}, kStart) {}
  /// The fix of the epoch `ms` after kStart.
  nmea::Fix at(int ms) {
    const UtcNs t = kStart + milliseconds(ms);
    nmea::Fix fix;
    fix.time_utc = floor<milliseconds>(t);
    fix.quality = nmea::FixQuality::gps;
    fix.dimension = nmea::FixDimension::three_d;
    fix.satellites_used = 8;
    (void)test::apply_faults(timeline, t, fix, std::nullopt, frame);
    return fix;
  }
  LocalFrame frame;
  FaultTimeline timeline;
};

TEST(LeapSecondFault, AnnouncedThenSecond60ThenOneSecondBehindWithGpsTimeContinuous) {
  Epochs run(leap_fault());
  std::uint32_t last_tow = 0;
  for (int ms = 0; ms <= 5000; ms += 250) {
    const nmea::Fix f = run.at(ms);
    const nmea::UtcTime clock = floor<milliseconds>(kStart + milliseconds(ms));
    if (ms > 0) {
      EXPECT_EQ(ubx::gps_time(f).tow_ms, last_tow + 250) << "GPS time steps with the epochs at +" << ms;
    }
    last_tow = ubx::gps_time(f).tow_ms;
    ASSERT_TRUE(f.leap.event_day.has_value());
    EXPECT_EQ(*f.leap.event_day, sys_days{year{2026} / December / 31});
    if (clock < kEvent) {
      EXPECT_EQ(f.time_utc, clock) << ms;
      EXPECT_FALSE(f.leap.in_second_60);
      EXPECT_EQ(f.leap.gps_minus_utc_s, 18);
      EXPECT_EQ(f.leap.change_s, 1) << "announced";
      EXPECT_EQ(f.leap.time_to_event_s, ceil<seconds>(kEvent - clock).count()) << ms;
    } else {
      EXPECT_EQ(f.time_utc, clock - seconds(1)) << ms;
      EXPECT_EQ(f.leap.in_second_60, clock < kEvent + seconds(1)) << ms;
      EXPECT_EQ(f.leap.gps_minus_utc_s, 19);
      EXPECT_EQ(f.leap.change_s, 0) << "no change announced after it";
      EXPECT_EQ(f.leap.time_to_event_s, -floor<seconds>(clock - kEvent).count()) << ms;
    }
  }
  Epochs again(leap_fault());
  EXPECT_EQ(again.at(2750).leap.time_to_event_s, 1);
  const nmea::Fix first = again.at(3000);
  EXPECT_EQ(first.time_utc, kEvent - seconds(1)) << "the event's first instant is 23:59:60.000 (time_utc 23:59:59)";
  EXPECT_TRUE(first.leap.in_second_60);
  EXPECT_EQ(again.at(3500).leap.time_to_event_s, 0) << "the event is now";
  const nmea::Fix next = again.at(4000);
  EXPECT_EQ(next.leap.time_to_event_s, -1);
  EXPECT_FALSE(next.leap.in_second_60);
  EXPECT_EQ(next.time_utc, kEvent) << "00:00:00.000 of the new day, a second after the clock's";
}

TEST(LeapSecondFault, BeforeItsStartNothingIsAnnounced) {
  Epochs run(leap_fault(1.0));
  const nmea::Fix before = run.at(500);
  EXPECT_FALSE(before.leap.event_day.has_value());
  EXPECT_EQ(before.leap.change_s, 0);
  EXPECT_EQ(run.at(1000).leap.change_s, 1);
}

TEST(LeapSecondFault, UbxTimeMessagesCarrySecond60AndTheNewCount) {
  Epochs run(leap_fault());
  ubx::NavExtras extras;
  const nmea::Fix before = run.at(1000), inside = run.at(3500), after = run.at(4500);
  // NAV-PVT: year 4, month 6, day 7, hour 8, min 9, sec 10.
  const std::string pvt = ubx::nav_pvt(inside, extras);
  EXPECT_EQ(ubx::get_u2(pvt, 4), 2026);
  EXPECT_EQ(ubx::get_u1(pvt, 6), 12);
  EXPECT_EQ(ubx::get_u1(pvt, 7), 31);
  EXPECT_EQ(ubx::get_u1(pvt, 8), 23);
  EXPECT_EQ(ubx::get_u1(pvt, 9), 59);
  EXPECT_EQ(ubx::get_u1(pvt, 10), 60);
  EXPECT_EQ(ubx::get_i4(pvt, 16), 500'000'000) << "nano";
  EXPECT_EQ(ubx::get_u1(ubx::nav_pvt(after, extras), 10), 0);
  EXPECT_EQ(ubx::get_u1(ubx::nav_pvt(after, extras), 7), 1);
  // NAV-TIMEUTC: sec 18.
  EXPECT_EQ(ubx::get_u1(ubx::nav_timeutc(inside, extras), 18), 60);
  // NAV-TIMEGPS: leapS 10.
  EXPECT_EQ(static_cast<std::int8_t>(ubx::get_u1(ubx::nav_timegps(before, extras), 10)), 18);
  EXPECT_EQ(static_cast<std::int8_t>(ubx::get_u1(ubx::nav_timegps(inside, extras), 10)), 19);
  EXPECT_EQ(static_cast<std::int8_t>(ubx::get_u1(ubx::nav_timegps(after, extras), 10)), 19);
  // NAV-TIMELS: currLs 9, lsChange 11, timeToLsEvent 12, dateOfLsGpsWn 16, dateOfLsGpsDn 18, valid 23.
  const std::string ls_before = ubx::nav_timels(before, extras);
  EXPECT_EQ(static_cast<std::int8_t>(ubx::get_u1(ls_before, 9)), 18);
  EXPECT_EQ(ubx::get_u1(ls_before, 10), 2) << "srcOfLsChange: GPS";
  EXPECT_EQ(static_cast<std::int8_t>(ubx::get_u1(ls_before, 11)), 1);
  EXPECT_EQ(ubx::get_i4(ls_before, 12), 2);
  EXPECT_EQ(ubx::get_u2(ls_before, 16), 2451) << "GPS week of 2026-12-31";
  EXPECT_EQ(ubx::get_u2(ls_before, 18), 5) << "Thursday (Sunday 1)";
  EXPECT_EQ(ubx::get_u1(ls_before, 23), 0x03) << "validCurrLs, validTimeToLsEvent";
  const std::string ls_after = ubx::nav_timels(after, extras);
  EXPECT_EQ(static_cast<std::int8_t>(ubx::get_u1(ls_after, 9)), 19);
  EXPECT_EQ(static_cast<std::int8_t>(ubx::get_u1(ls_after, 11)), 0);
  EXPECT_EQ(ubx::get_i4(ls_after, 12), -1);
  EXPECT_EQ(ubx::get_u2(ls_after, 16), 2451) << "the last event";
  // Without the fault: 18, nothing announced, the 2016 event.
  const std::string ls_default = ubx::nav_timels(nmea::Fix{}, extras);
  EXPECT_EQ(static_cast<std::int8_t>(ubx::get_u1(ls_default, 9)), 18);
  EXPECT_EQ(static_cast<std::int8_t>(ubx::get_u1(ls_default, 11)), 0);
  EXPECT_EQ(ubx::get_u2(ls_default, 16), 1929);
  // An event centuries away: timeToLsEvent held at its 32-bit limit, not wrapped.
  nmea::Fix far = before;
  far.leap.time_to_event_s = 60'000'000'000;
  EXPECT_EQ(ubx::get_i4(ubx::nav_timels(far, extras), 12), INT32_MAX);
  // A receiver that does not know UTC yet: nothing valid, nothing announced.
  ubx::NavExtras cold;
  cold.time.resolved = false;
  const std::string ls_cold = ubx::nav_timels(before, cold);
  EXPECT_EQ(ubx::get_u1(ls_cold, 11), 0);
  EXPECT_EQ(ubx::get_u1(ls_cold, 23), 0);
}

TEST(LeapSecondFault, ItsKeysAreRefusedWithTheReason) {
  const auto refused = test::expect_fault_refused;
  refused({{"kind", std::string("time")}, {"mode", std::string("leap-second")}}, "leap_utc: missing");
  refused({{"kind", std::string("time")}, {"mode", std::string("leap-second")}, {"leap_utc", std::string("2026-12-31T23:59:59Z")}},
          "expected the inserted second as YYYY-MM-DDT23:59:60Z");
  refused({{"kind", std::string("time")}, {"mode", std::string("leap-second")}, {"leap_utc", std::string("2026-13-31T23:59:60Z")}},
          "leap_utc: expected");
  refused({{"kind", std::string("time")}, {"mode", std::string("leap-second")}, {"leap_utc", 5.0}}, "leap_utc: expected a string");
  refused({{"kind", std::string("time")}, {"mode", std::string("jump")}, {"jump_s", 1.0}, {"leap_utc", std::string("2026-12-31T23:59:60Z")}},
          "leap_utc: a parameter of mode = \"leap-second\" only");
  refused({{"kind", std::string("time")}, {"mode", std::string("leap-second")}, {"jump_s", 1.0},
           {"leap_utc", std::string("2026-12-31T23:59:60Z")}},
          "jump_s: not a parameter of a leap second");
  refused({{"kind", std::string("time")}, {"mode", std::string("leap")}}, "expected jump, rollover or leap-second");
  EXPECT_EQ(leap_fault().parameters(), "time mode=leap-second leap_utc=2026-12-31T23:59:60Z");
}

}  // namespace leap_second_test
}  // namespace
}  // namespace gpsemu::faults
