// NAV message payloads (see nav.hpp).
#include "emulator/ubx/nav.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <GeographicLib/Geocentric.hpp>

#include "emulator/model/accuracy.hpp"
#include "emulator/rtk/correction_age.hpp"
#include "emulator/ubx/layouts.hpp"

namespace gpsemu::ubx {
namespace {

using std::chrono::milliseconds;

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr std::uint32_t kTimeAccuracyNs = 20;  // tAcc with a fix (ns)
constexpr std::uint32_t kNoFixTimeAccuracyNs = 1'000'000'000;

// Out-of-range values saturate; NaN becomes 0 (a fix never carries one, a fuzzer does).
std::int32_t round_i32(double v) {
  if (std::isnan(v)) return 0;
  const double clamped = std::clamp(std::round(v), -2147483648.0, 2147483647.0);
  return static_cast<std::int32_t>(clamped);
}
std::uint32_t round_u32(double v) {
  if (std::isnan(v)) return 0;
  return static_cast<std::uint32_t>(std::clamp(std::round(v), 0.0, 4294967295.0));
}
std::uint32_t round_u16(double v) {
  if (std::isnan(v)) return 0;
  return static_cast<std::uint32_t>(std::clamp(std::round(v), 0.0, 65535.0));
}

/// What the fix says about the solution, in u-blox's terms.
struct Solution {
  std::uint8_t fix_type = 0;  // 0 none, 1 dead reckoning, 2 2-D, 3 3-D
  bool fix_ok = false;        // gnssFixOK
  bool differential = false;  // diffSoln
  std::uint8_t carrier = 0;   // carrSoln: 0 none, 1 float, 2 fixed
};

Solution solution_of(const nmea::Fix& fix) {
  using Q = nmea::FixQuality;
  Solution s;
  if (!fix.has_fix()) return s;
  if (fix.quality == Q::estimated) {
    s.fix_type = 1;
    return s;
  }
  s.fix_type = fix.dimension == nmea::FixDimension::two_d ? 2 : 3;
  s.fix_ok = true;
  s.differential = fix.quality == Q::dgps || fix.quality == Q::rtk_float || fix.quality == Q::rtk_fixed;
  s.carrier = fix.quality == Q::rtk_float ? 1 : fix.quality == Q::rtk_fixed ? 2 : 0;
  return s;
}

/// The fix's 1-sigma errors as the model reported them; the speed's at least its quality's floor
/// (the speed accuracy is not in the fix yet: a protocol setting).
struct Sigmas {
  double north_m = 0.0, east_m = 0.0, down_m = 0.0, speed_mps = 0.0;
};
Sigmas sigmas_of(const nmea::Fix& fix) { return {fix.sigma_lat_m, fix.sigma_lon_m, fix.sigma_alt_m, fix.sigma_speed_mps}; }
double h_acc_m(const nmea::Fix& fix) { return sky::horizontal_accuracy_m(fix); }
double v_acc_m(const nmea::Fix& fix) { return position_accuracy(fix).down_m; }
std::uint32_t h_acc_mm(const nmea::Fix& fix) { return fix.has_fix() ? round_u32(h_acc_m(fix) * 1000.0) : no_fix_accuracy_mm; }
std::uint32_t v_acc_mm(const nmea::Fix& fix) { return fix.has_fix() ? round_u32(v_acc_m(fix) * 1000.0) : no_fix_accuracy_mm; }
std::uint32_t s_acc_mm_s(const nmea::Fix& fix) {
  return fix.has_fix() ? round_u32(fix.sigma_speed_mps * 1000.0) : no_fix_speed_accuracy_mm_s;
}
/// Heading accuracy (degrees): the angle the speed error subtends, 180 when standing still;
/// never below 1e-5 degrees (its unit).
double head_acc_deg(const nmea::Fix& fix) {
  const double sigma_mps = fix.sigma_speed_mps;
  if (!fix.has_fix() || fix.speed_mps <= sigma_mps) return 180.0;
  return std::clamp(std::atan2(sigma_mps, fix.speed_mps) / kDegToRad, 1e-5, 180.0);
}

/// North, east and down velocity (metres per second); 0 without a fix.
struct VelocityNed {
  double north_mps = 0.0, east_mps = 0.0, down_mps = 0.0;
};
VelocityNed velocity_of(const nmea::Fix& fix) {
  if (!fix.has_fix()) return {};
  const double course_rad = fix.course_deg_true.value_or(0.0) * kDegToRad;
  return {fix.speed_mps * std::cos(course_rad), fix.speed_mps * std::sin(course_rad), -fix.vel_up_mps};
}

std::uint32_t tow_ms(const nmea::Fix& fix) { return gps_time(fix).tow_ms; }

/// NAV-STATUS / NAV-SOL flags: gpsFixOK, diffSoln, WKNSET, TOWSET (once the time is known).
std::uint8_t status_flags(const Solution& s, const TimeValidity& time) {
  return static_cast<std::uint8_t>((s.fix_ok ? 0x01 : 0) | (s.differential ? 0x02 : 0) | (time.valid ? 0x0C : 0));
}

struct UtcFields {
  int year = 0;
  unsigned month = 0, day = 0, hour = 0, minute = 0, second = 0;
  std::int32_t nano = 0;
};
/// The fix's UTC date and time; inside an inserted leap second sec is 60 (the date the old day's).
UtcFields utc_fields(const nmea::Fix& fix) {
  const nmea::UtcTime t = fix.time_utc;
  const auto day_point = std::chrono::floor<std::chrono::days>(t);
  const std::chrono::year_month_day ymd{day_point};
  const std::chrono::hh_mm_ss<milliseconds> hms{t - day_point};
  return {static_cast<int>(ymd.year()),           static_cast<unsigned>(ymd.month()),
          static_cast<unsigned>(ymd.day()),       static_cast<unsigned>(hms.hours().count()),
          static_cast<unsigned>(hms.minutes().count()),
          static_cast<unsigned>(hms.seconds().count()) + (fix.leap.in_second_60 ? 1u : 0u),
          static_cast<std::int32_t>(hms.subseconds().count() * 1'000'000)};
}

/// lon, lat (1e-7 deg), height above the ellipsoid and above mean sea level (mm), hAcc, vAcc (mm):
/// the position fields NAV-PVT and NAV-POSLLH share.
template <class Writer>
void set_llh_position(Writer& w, const nmea::Fix& fix) {
  w.template set<"lon">(fix.has_fix() ? round_i32(fix.lon_deg * 1e7) : 0);
  w.template set<"lat">(fix.has_fix() ? round_i32(fix.lat_deg * 1e7) : 0);
  w.template set<"height">(fix.has_fix() ? round_i32((fix.alt_msl_m + fix.geoid_sep_m) * 1000.0) : 0);
  w.template set<"hMSL">(fix.has_fix() ? round_i32(fix.alt_msl_m * 1000.0) : 0);
  w.template set<"hAcc">(h_acc_mm(fix));
  w.template set<"vAcc">(v_acc_mm(fix));
}

/// year, month, day, hour, min, sec: the date-time fields NAV-PVT and NAV-TIMEUTC share.
template <class Writer>
void set_date_time(Writer& w, const UtcFields& utc) {
  w.template set<"year">(utc.year);
  w.template set<"month">(utc.month);
  w.template set<"day">(utc.day);
  w.template set<"hour">(utc.hour);
  w.template set<"min">(utc.minute);
  w.template set<"sec">(utc.second);
}

/// WGS84 earth-centred, earth-fixed coordinates (metres) of the fix's position.
struct Ecef {
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
};
Ecef ecef_of(const nmea::Fix& fix) {
  Ecef e;
  GeographicLib::Geocentric::WGS84().Forward(fix.lat_deg, fix.lon_deg, fix.alt_msl_m + fix.geoid_sep_m, e.x_m, e.y_m,
                                             e.z_m);
  return e;
}
}  // namespace

NedAccuracy position_accuracy(const nmea::Fix& fix) {
  const Sigmas s = sigmas_of(fix);
  return {s.north_m, s.east_m, s.down_m};
}

std::string nav_pvt(const nmea::Fix& fix, const NavExtras& extras) {
  const Solution s = solution_of(fix);
  const UtcFields utc = utc_fields(fix);
  const VelocityNed v = velocity_of(fix);
  PayloadWriter<layout::nav_pvt> w;
  w.set<"iTOW">(tow_ms(fix));
  set_date_time(w, utc);
  // valid: validDate, validTime, fullyResolved
  w.set<"valid">((extras.time.valid ? 0x03u : 0u) | (extras.time.valid && extras.time.resolved ? 0x04u : 0u));
  w.set<"tAcc">(fix.has_fix() ? kTimeAccuracyNs : kNoFixTimeAccuracyNs);
  w.set<"nano">(utc.nano);
  w.set<"fixType">(s.fix_type);
  w.set<"flags">((s.fix_ok ? 0x01u : 0u) | (s.differential ? 0x02u : 0u) | (static_cast<unsigned>(s.carrier) << 6));
  w.set<"flags2">(0x20u | (extras.time.confirmed ? 0xC0u : 0u));  // confirmedAvai, confirmedDate, confirmedTime
  w.set<"numSV">(fix.has_fix() ? fix.satellites_used : 0);
  set_llh_position(w, fix);
  w.set<"velN">(round_i32(v.north_mps * 1000.0));
  w.set<"velE">(round_i32(v.east_mps * 1000.0));
  w.set<"velD">(round_i32(v.down_mps * 1000.0));
  w.set<"gSpeed">(fix.has_fix() ? round_i32(fix.speed_mps * 1000.0) : 0);
  w.set<"headMot">(fix.has_fix() ? round_i32(fix.course_deg_true.value_or(0.0) * 1e5) : 0);
  w.set<"sAcc">(s_acc_mm_s(fix));
  w.set<"headAcc">(round_u32(head_acc_deg(fix) * 1e5));
  w.set<"pDOP">(fix.has_fix() ? round_u16(fix.pdop * 100.0) : 9999);
  // flags3: invalidLlh, lastCorrectionAge; headVeh 0 (headVehValid is not set), magDec, magAcc 0
  w.set<"flags3">((fix.has_fix() ? 0u : 1u) | (rtk::last_correction_age_code(fix.diff_age_s) << 1));
  return std::move(w).bytes();
}

std::string nav_posllh(const nmea::Fix& fix) {
  PayloadWriter<layout::nav_posllh> w;
  w.set<"iTOW">(tow_ms(fix));
  set_llh_position(w, fix);
  return std::move(w).bytes();
}

std::string nav_velned(const nmea::Fix& fix, const NavExtras& /*extras*/) {
  const VelocityNed v = velocity_of(fix);
  const double speed_mps = fix.has_fix() ? fix.speed_mps : 0.0;
  PayloadWriter<layout::nav_velned> w;
  w.set<"iTOW">(tow_ms(fix));
  w.set<"velN">(round_i32(v.north_mps * 100.0));
  w.set<"velE">(round_i32(v.east_mps * 100.0));
  w.set<"velD">(round_i32(v.down_mps * 100.0));
  w.set<"speed">(round_u32(std::hypot(speed_mps, v.down_mps) * 100.0));
  w.set<"gSpeed">(round_u32(speed_mps * 100.0));
  w.set<"heading">(fix.has_fix() ? round_i32(fix.course_deg_true.value_or(0.0) * 1e5) : 0);
  w.set<"sAcc">((s_acc_mm_s(fix) + 5) / 10);
  w.set<"cAcc">(round_u32(head_acc_deg(fix) * 1e5));
  return std::move(w).bytes();
}

std::string nav_status(const nmea::Fix& fix, const NavExtras& extras) {
  const Solution s = solution_of(fix);
  PayloadWriter<layout::nav_status> w;
  w.set<"iTOW">(tow_ms(fix));
  w.set<"gpsFix">(s.fix_type);
  w.set<"flags">(status_flags(s, extras.time));
  w.set<"fixStat">((s.differential ? 0x01u : 0u) | (s.carrier != 0 ? 0x02u : 0u));  // diffCorr, carrSolnValid
  // flags2: carrSoln, spoofDetState
  w.set<"flags2">(static_cast<std::uint32_t>(s.carrier) << 6 | (extras.rf.spoof_detection_state & 3u) << 3);
  w.set<"ttff">(static_cast<std::uint32_t>(extras.time_to_first_fix.count()));
  w.set<"msss">(static_cast<std::uint32_t>(extras.since_start.count()));
  return std::move(w).bytes();
}

namespace {

/// The ECEF position (cm) and its accuracy (cm): NAV-SOL's and NAV-POSECEF's fields.
template <class Writer>
void set_ecef_position(Writer& w, const nmea::Fix& fix) {
  const Ecef e = fix.has_fix() ? ecef_of(fix) : Ecef{};
  w.template set<"ecefX">(round_i32(e.x_m * 100.0));
  w.template set<"ecefY">(round_i32(e.y_m * 100.0));
  w.template set<"ecefZ">(round_i32(e.z_m * 100.0));
  w.template set<"pAcc">(fix.has_fix() ? round_u32(std::hypot(h_acc_m(fix), v_acc_m(fix)) * 100.0)
                                       : no_fix_accuracy_mm / 10);
}

/// The ECEF velocity (cm/s, rotated from NED) and the speed accuracy (cm/s): NAV-SOL's and
/// NAV-VELECEF's fields.
template <class Writer>
void set_ecef_velocity(Writer& w, const nmea::Fix& fix, const NavExtras& /*extras*/) {
  const VelocityNed v = velocity_of(fix);
  const double lat = fix.lat_deg * kDegToRad;
  const double lon = fix.lon_deg * kDegToRad;
  const double vx = -std::sin(lat) * std::cos(lon) * v.north_mps - std::sin(lon) * v.east_mps -
                    std::cos(lat) * std::cos(lon) * v.down_mps;
  const double vy = -std::sin(lat) * std::sin(lon) * v.north_mps + std::cos(lon) * v.east_mps -
                    std::cos(lat) * std::sin(lon) * v.down_mps;
  const double vz = std::cos(lat) * v.north_mps - std::sin(lat) * v.down_mps;
  w.template set<"ecefVX">(round_i32(vx * 100.0));
  w.template set<"ecefVY">(round_i32(vy * 100.0));
  w.template set<"ecefVZ">(round_i32(vz * 100.0));
  w.template set<"sAcc">((s_acc_mm_s(fix) + 5) / 10);
}

}  // namespace

std::string nav_sol(const nmea::Fix& fix, const NavExtras& extras) {
  const Solution s = solution_of(fix);
  const GpsTime t = gps_time(fix);
  PayloadWriter<layout::nav_sol> w;
  w.set<"iTOW">(t.tow_ms);
  w.set<"fTOW">(0);  // epochs lie on whole milliseconds
  w.set<"week">(t.week);
  w.set<"gpsFix">(s.fix_type);
  w.set<"flags">(status_flags(s, extras.time));
  set_ecef_position(w, fix);
  set_ecef_velocity(w, fix, extras);
  w.set<"pDOP">(fix.has_fix() ? round_u16(fix.pdop * 100.0) : 9999);
  w.set<"numSV">(fix.has_fix() ? fix.satellites_used : 0);
  return std::move(w).bytes();
}

std::string nav_posecef(const nmea::Fix& fix) {
  PayloadWriter<layout::nav_posecef> w;
  w.set<"iTOW">(tow_ms(fix));
  set_ecef_position(w, fix);
  return std::move(w).bytes();
}

std::string nav_velecef(const nmea::Fix& fix, const NavExtras& extras) {
  PayloadWriter<layout::nav_velecef> w;
  w.set<"iTOW">(tow_ms(fix));
  set_ecef_velocity(w, fix, extras);
  return std::move(w).bytes();
}

std::string nav_dop(const nmea::Fix& fix) {
  const bool ok = fix.has_fix();
  const double tdop = fix.tdop > 0.0 ? fix.tdop : 0.6 * fix.pdop;
  const double gdop = fix.gdop > 0.0 ? fix.gdop : std::hypot(fix.pdop, tdop);
  const auto dop = [ok](double value) { return ok ? round_u16(value * 100.0) : 9999u; };
  PayloadWriter<layout::nav_dop> w;
  w.set<"iTOW">(tow_ms(fix));
  w.set<"gDOP">(dop(gdop));
  w.set<"pDOP">(dop(fix.pdop));
  w.set<"tDOP">(dop(tdop));
  w.set<"vDOP">(dop(fix.vdop));
  w.set<"hDOP">(dop(fix.hdop));
  w.set<"nDOP">(dop(fix.hdop / std::numbers::sqrt2));
  w.set<"eDOP">(dop(fix.hdop / std::numbers::sqrt2));
  return std::move(w).bytes();
}

std::string nav_timeutc(const nmea::Fix& fix, const NavExtras& extras) {
  const UtcFields utc = utc_fields(fix);
  PayloadWriter<layout::nav_timeutc> w;
  w.set<"iTOW">(tow_ms(fix));
  w.set<"tAcc">(fix.has_fix() ? kTimeAccuracyNs : kNoFixTimeAccuracyNs);
  w.set<"nano">(utc.nano);
  set_date_time(w, utc);
  // validTOW, validWKN, validUTC; utcStandard 3 (USNO) once UTC is known
  const bool utc_known = extras.time.valid && extras.time.resolved;
  w.set<"valid">((extras.time.valid ? 0x03u : 0u) | (utc_known ? 0x34u : 0u));
  return std::move(w).bytes();
}

std::string nav_timegps(const nmea::Fix& fix, const NavExtras& extras) {
  const GpsTime t = gps_time(fix);
  PayloadWriter<layout::nav_timegps> w;
  w.set<"iTOW">(t.tow_ms);
  w.set<"fTOW">(0);
  w.set<"week">(t.week);
  w.set<"leapS">(fix.leap.gps_minus_utc_s);
  // towValid, weekValid, leapSValid
  w.set<"valid">((extras.time.valid ? 0x03u : 0u) | (extras.time.valid && extras.time.resolved ? 0x04u : 0u));
  w.set<"tAcc">(fix.has_fix() ? kTimeAccuracyNs : kNoFixTimeAccuracyNs);
  return std::move(w).bytes();
}

std::string nav_cov(const nmea::Fix& fix, const NavExtras& /*extras*/) {
  const bool ok = fix.has_fix();
  const auto sq = [ok](double v) { return ok ? static_cast<float>(v * v) : 0.0f; };
  const Sigmas sigma = sigmas_of(fix);
  PayloadWriter<layout::nav_cov> w;
  w.set<"iTOW">(tow_ms(fix));
  w.set<"version">(0);
  w.set<"posCovValid">(ok ? 1u : 0u);
  w.set<"velCovValid">(ok ? 1u : 0u);
  // Off-diagonal terms 0.
  w.set<"posCovNN">(sq(sigma.north_m));
  w.set<"posCovEE">(sq(sigma.east_m));
  w.set<"posCovDD">(sq(sigma.down_m));
  w.set<"velCovNN">(sq(sigma.speed_mps));
  w.set<"velCovEE">(sq(sigma.speed_mps));
  w.set<"velCovDD">(sq(sigma.speed_mps));
  return std::move(w).bytes();
}

std::string nav_clock(const nmea::Fix& fix, const NavExtras& extras) {
  PayloadWriter<layout::nav_clock> w;
  w.set<"iTOW">(tow_ms(fix));
  w.set<"clkB">(extras.clock.bias_ns);
  w.set<"clkD">(extras.clock.drift_ns_per_s);
  w.set<"tAcc">(extras.clock.time_accuracy_ns);
  w.set<"fAcc">(extras.clock.frequency_accuracy_ps_per_s);
  return std::move(w).bytes();
}

std::string nav_hpposllh(const nmea::Fix& fix) {
  const bool ok = fix.has_fix();
  // A value in units of 1e-7 deg (or mm) and its remainder in 1e-9 deg (0.1 mm), both rounded
  // toward zero so that they add up: -99..99 (-9..9).
  const auto split = [](double fine_units, int ratio, std::int32_t& coarse, std::int32_t& rest) {
    const double total = std::clamp(std::round(fine_units), -9.2e18, 9.2e18);
    const auto whole = static_cast<std::int64_t>(total);
    coarse = static_cast<std::int32_t>(std::clamp<std::int64_t>(whole / ratio, INT32_MIN, INT32_MAX));
    rest = static_cast<std::int32_t>(whole % ratio);
  };
  std::int32_t lon = 0, lon_hp = 0, lat = 0, lat_hp = 0, height = 0, height_hp = 0, msl = 0, msl_hp = 0;
  if (ok && !std::isnan(fix.lat_deg + fix.lon_deg + fix.alt_msl_m + fix.geoid_sep_m)) {
    split(fix.lon_deg * 1e9, 100, lon, lon_hp);
    split(fix.lat_deg * 1e9, 100, lat, lat_hp);
    split((fix.alt_msl_m + fix.geoid_sep_m) * 1e4, 10, height, height_hp);
    split(fix.alt_msl_m * 1e4, 10, msl, msl_hp);
  }
  PayloadWriter<layout::nav_hpposllh> w;
  w.set<"version">(0);
  w.set<"flags">(ok ? 0u : 1u);  // invalidLlh
  w.set<"iTOW">(tow_ms(fix));
  w.set<"lon">(lon);
  w.set<"lat">(lat);
  w.set<"height">(height);
  w.set<"hMSL">(msl);
  w.set<"lonHp">(lon_hp);
  w.set<"latHp">(lat_hp);
  w.set<"heightHp">(height_hp);
  w.set<"hMSLHp">(msl_hp);
  w.set<"hAcc">(ok ? round_u32(h_acc_m(fix) * 1e4) : no_fix_accuracy_mm);  // 0.1 mm
  w.set<"vAcc">(ok ? round_u32(v_acc_m(fix) * 1e4) : no_fix_accuracy_mm);
  return std::move(w).bytes();
}

std::string nav_eoe(const nmea::Fix& fix) {
  PayloadWriter<layout::nav_eoe> w;
  w.set<"iTOW">(tow_ms(fix));
  return std::move(w).bytes();
}

}  // namespace gpsemu::ubx
