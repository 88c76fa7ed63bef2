// NAV message payloads (see nav.hpp).
#include "emulator/ubx/nav.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <GeographicLib/Geocentric.hpp>

#include "emulator/ubx/bytes.hpp"

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

double h_acc_m(const nmea::Fix& fix) { return std::hypot(fix.sigma_lat_m, fix.sigma_lon_m); }
std::uint32_t h_acc_mm(const nmea::Fix& fix) { return fix.has_fix() ? round_u32(h_acc_m(fix) * 1000.0) : no_fix_accuracy_mm; }
std::uint32_t v_acc_mm(const nmea::Fix& fix) {
  return fix.has_fix() ? round_u32(fix.sigma_alt_m * 1000.0) : no_fix_accuracy_mm;
}
std::uint32_t s_acc_mm_s(const nmea::Fix& fix, const NavExtras& extras) {
  return fix.has_fix() ? round_u32(extras.speed_sigma_mps * 1000.0) : no_fix_speed_accuracy_mm_s;
}
/// Heading accuracy (degrees): the angle the speed error subtends, 180 when standing still.
double head_acc_deg(const nmea::Fix& fix, const NavExtras& extras) {
  if (!fix.has_fix() || fix.speed_mps <= extras.speed_sigma_mps) return 180.0;
  return std::min(180.0, std::atan2(extras.speed_sigma_mps, fix.speed_mps) / kDegToRad);
}

/// North and east velocity (metres per second); 0 without a fix.
struct VelocityNed {
  double north_mps = 0.0, east_mps = 0.0, down_mps = 0.0;
};
VelocityNed velocity_of(const nmea::Fix& fix) {
  if (!fix.has_fix()) return {};
  const double course_rad = fix.course_deg_true.value_or(0.0) * kDegToRad;
  return {fix.speed_mps * std::cos(course_rad), fix.speed_mps * std::sin(course_rad), 0.0};
}

std::uint32_t tow_ms(const nmea::Fix& fix) { return gps_time(fix.time_utc).tow_ms; }

/// NAV-STATUS / NAV-SOL flags: gpsFixOK, diffSoln, WKNSET, TOWSET.
std::uint8_t status_flags(const Solution& s) {
  return static_cast<std::uint8_t>((s.fix_ok ? 0x01 : 0) | (s.differential ? 0x02 : 0) | 0x0C);
}

struct UtcFields {
  int year = 0;
  unsigned month = 0, day = 0, hour = 0, minute = 0, second = 0;
  std::int32_t nano = 0;
};
UtcFields utc_fields(nmea::UtcTime t) {
  const auto day_point = std::chrono::floor<std::chrono::days>(t);
  const std::chrono::year_month_day ymd{day_point};
  const std::chrono::hh_mm_ss<milliseconds> hms{t - day_point};
  return {static_cast<int>(ymd.year()),           static_cast<unsigned>(ymd.month()),
          static_cast<unsigned>(ymd.day()),       static_cast<unsigned>(hms.hours().count()),
          static_cast<unsigned>(hms.minutes().count()), static_cast<unsigned>(hms.seconds().count()),
          static_cast<std::int32_t>(hms.subseconds().count() * 1'000'000)};
}

/// lon, lat (1e-7 deg), height above the ellipsoid and above mean sea level (mm), hAcc, vAcc (mm):
/// the position block NAV-PVT and NAV-POSLLH share.
void put_llh_position(std::string& p, const nmea::Fix& fix) {
  put_i4(p, fix.has_fix() ? round_i32(fix.lon_deg * 1e7) : 0);
  put_i4(p, fix.has_fix() ? round_i32(fix.lat_deg * 1e7) : 0);
  put_i4(p, fix.has_fix() ? round_i32((fix.alt_msl_m + fix.geoid_sep_m) * 1000.0) : 0);
  put_i4(p, fix.has_fix() ? round_i32(fix.alt_msl_m * 1000.0) : 0);
  put_u4(p, h_acc_mm(fix));
  put_u4(p, v_acc_mm(fix));
}

/// Year (2 bytes), month, day, hour, minute, second: the date-time block NAV-PVT and NAV-TIMEUTC share.
void put_date_time(std::string& p, const UtcFields& utc) {
  put_u2(p, static_cast<std::uint32_t>(utc.year));
  put_u1(p, utc.month);
  put_u1(p, utc.day);
  put_u1(p, utc.hour);
  put_u1(p, utc.minute);
  put_u1(p, utc.second);
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

GpsTime gps_time(nmea::UtcTime utc) {
  using namespace std::chrono;
  constexpr sys_days gps_epoch{year{1980} / January / 6};
  const milliseconds since = utc - time_point_cast<milliseconds>(gps_epoch) + seconds{gps_leap_seconds};
  constexpr milliseconds week = duration_cast<milliseconds>(weeks{1});
  const auto w = since / week;
  return {static_cast<int>(w), static_cast<std::uint32_t>((since - w * week).count())};
}

std::string nav_pvt(const nmea::Fix& fix, const NavExtras& extras) {
  const Solution s = solution_of(fix);
  const UtcFields utc = utc_fields(fix.time_utc);
  const VelocityNed v = velocity_of(fix);
  std::string p;
  p.reserve(92);
  put_u4(p, tow_ms(fix));
  put_date_time(p, utc);
  put_u1(p, 0x07);  // valid: validDate, validTime, fullyResolved
  put_u4(p, fix.has_fix() ? kTimeAccuracyNs : kNoFixTimeAccuracyNs);
  put_i4(p, utc.nano);
  put_u1(p, s.fix_type);
  put_u1(p, (s.fix_ok ? 0x01u : 0u) | (s.differential ? 0x02u : 0u) | (static_cast<unsigned>(s.carrier) << 6));
  put_u1(p, 0xE0);  // flags2: confirmedAvai, confirmedDate, confirmedTime
  put_u1(p, static_cast<std::uint32_t>(fix.has_fix() ? fix.satellites_used : 0));
  put_llh_position(p, fix);
  put_i4(p, round_i32(v.north_mps * 1000.0));
  put_i4(p, round_i32(v.east_mps * 1000.0));
  put_i4(p, round_i32(v.down_mps * 1000.0));
  put_i4(p, fix.has_fix() ? round_i32(fix.speed_mps * 1000.0) : 0);
  put_i4(p, fix.has_fix() ? round_i32(fix.course_deg_true.value_or(0.0) * 1e5) : 0);
  put_u4(p, s_acc_mm_s(fix, extras));
  put_u4(p, round_u32(head_acc_deg(fix, extras) * 1e5));
  put_u2(p, fix.has_fix() ? round_u16(fix.pdop * 100.0) : 9999);
  put_u2(p, fix.has_fix() ? 0u : 1u);  // flags3: invalidLlh
  put_zeros(p, 4);                      // reserved
  put_i4(p, 0);                         // headVeh (headVehValid is not set)
  put_i2(p, 0);                         // magDec
  put_u2(p, 0);                         // magAcc
  return p;
}

std::string nav_posllh(const nmea::Fix& fix) {
  std::string p;
  put_u4(p, tow_ms(fix));
  put_llh_position(p, fix);
  return p;
}

std::string nav_velned(const nmea::Fix& fix, const NavExtras& extras) {
  const VelocityNed v = velocity_of(fix);
  const double speed_mps = fix.has_fix() ? fix.speed_mps : 0.0;
  std::string p;
  put_u4(p, tow_ms(fix));
  put_i4(p, round_i32(v.north_mps * 100.0));
  put_i4(p, round_i32(v.east_mps * 100.0));
  put_i4(p, round_i32(v.down_mps * 100.0));
  put_u4(p, round_u32(std::hypot(speed_mps, v.down_mps) * 100.0));
  put_u4(p, round_u32(speed_mps * 100.0));
  put_i4(p, fix.has_fix() ? round_i32(fix.course_deg_true.value_or(0.0) * 1e5) : 0);
  put_u4(p, (s_acc_mm_s(fix, extras) + 5) / 10);
  put_u4(p, round_u32(head_acc_deg(fix, extras) * 1e5));
  return p;
}

std::string nav_status(const nmea::Fix& fix, const NavExtras& extras) {
  const Solution s = solution_of(fix);
  std::string p;
  put_u4(p, tow_ms(fix));
  put_u1(p, s.fix_type);
  put_u1(p, status_flags(s));
  put_u1(p, (s.differential ? 0x01u : 0u) | (s.carrier != 0 ? 0x02u : 0u));  // fixStat: diffCorr, carrSolnValid
  put_u1(p, static_cast<std::uint32_t>(s.carrier) << 6);                     // flags2: carrSoln
  put_u4(p, static_cast<std::uint32_t>(extras.time_to_first_fix.count()));
  put_u4(p, static_cast<std::uint32_t>(extras.since_start.count()));
  return p;
}

/// The ECEF position (cm) and its accuracy (cm): NAV-SOL's and NAV-POSECEF's fields.
void put_ecef_position(std::string& p, const nmea::Fix& fix) {
  const Ecef e = fix.has_fix() ? ecef_of(fix) : Ecef{};
  put_i4(p, round_i32(e.x_m * 100.0));
  put_i4(p, round_i32(e.y_m * 100.0));
  put_i4(p, round_i32(e.z_m * 100.0));
  put_u4(p, fix.has_fix() ? round_u32(std::hypot(h_acc_m(fix), fix.sigma_alt_m) * 100.0) : no_fix_accuracy_mm / 10);
}

/// The ECEF velocity (cm/s, rotated from NED) and the speed accuracy (cm/s): NAV-SOL's and
/// NAV-VELECEF's fields.
void put_ecef_velocity(std::string& p, const nmea::Fix& fix, const NavExtras& extras) {
  const VelocityNed v = velocity_of(fix);
  const double lat = fix.lat_deg * kDegToRad;
  const double lon = fix.lon_deg * kDegToRad;
  const double vx = -std::sin(lat) * std::cos(lon) * v.north_mps - std::sin(lon) * v.east_mps -
                    std::cos(lat) * std::cos(lon) * v.down_mps;
  const double vy = -std::sin(lat) * std::sin(lon) * v.north_mps + std::cos(lon) * v.east_mps -
                    std::cos(lat) * std::sin(lon) * v.down_mps;
  const double vz = std::cos(lat) * v.north_mps - std::sin(lat) * v.down_mps;
  put_i4(p, round_i32(vx * 100.0));
  put_i4(p, round_i32(vy * 100.0));
  put_i4(p, round_i32(vz * 100.0));
  put_u4(p, (s_acc_mm_s(fix, extras) + 5) / 10);
}

std::string nav_sol(const nmea::Fix& fix, const NavExtras& extras) {
  const Solution s = solution_of(fix);
  const GpsTime t = gps_time(fix.time_utc);
  std::string p;
  put_u4(p, t.tow_ms);
  put_i4(p, 0);  // fTOW: epochs lie on whole milliseconds
  put_i2(p, t.week);
  put_u1(p, s.fix_type);
  put_u1(p, status_flags(s));
  put_ecef_position(p, fix);
  put_ecef_velocity(p, fix, extras);
  put_u2(p, fix.has_fix() ? round_u16(fix.pdop * 100.0) : 9999);
  put_u1(p, 0);  // reserved1
  put_u1(p, static_cast<std::uint32_t>(fix.has_fix() ? fix.satellites_used : 0));
  put_zeros(p, 4);  // reserved2
  return p;
}

std::string nav_posecef(const nmea::Fix& fix) {
  std::string p;
  put_u4(p, tow_ms(fix));
  put_ecef_position(p, fix);
  return p;
}

std::string nav_velecef(const nmea::Fix& fix, const NavExtras& extras) {
  std::string p;
  put_u4(p, tow_ms(fix));
  put_ecef_velocity(p, fix, extras);
  return p;
}

std::string nav_dop(const nmea::Fix& fix) {
  const bool ok = fix.has_fix();
  const double tdop = 0.6 * fix.pdop;
  const auto dop = [ok](double value) { return ok ? round_u16(value * 100.0) : 9999u; };
  std::string p;
  put_u4(p, tow_ms(fix));
  put_u2(p, dop(std::hypot(fix.pdop, tdop)));  // gDOP
  put_u2(p, dop(fix.pdop));
  put_u2(p, dop(tdop));
  put_u2(p, dop(fix.vdop));
  put_u2(p, dop(fix.hdop));
  put_u2(p, dop(fix.hdop / std::numbers::sqrt2));  // nDOP
  put_u2(p, dop(fix.hdop / std::numbers::sqrt2));  // eDOP
  return p;
}

std::string nav_timeutc(const nmea::Fix& fix) {
  const UtcFields utc = utc_fields(fix.time_utc);
  std::string p;
  put_u4(p, tow_ms(fix));
  put_u4(p, fix.has_fix() ? kTimeAccuracyNs : kNoFixTimeAccuracyNs);
  put_i4(p, utc.nano);
  put_date_time(p, utc);
  put_u1(p, 0x37);  // validTOW, validWKN, validUTC; utcStandard 3 (USNO)
  return p;
}

std::string nav_timegps(const nmea::Fix& fix) {
  const GpsTime t = gps_time(fix.time_utc);
  std::string p;
  put_u4(p, t.tow_ms);
  put_i4(p, 0);  // fTOW
  put_i2(p, t.week);
  put_i1(p, gps_leap_seconds);
  put_u1(p, 0x07);  // towValid, weekValid, leapSValid
  put_u4(p, fix.has_fix() ? kTimeAccuracyNs : kNoFixTimeAccuracyNs);
  return p;
}

std::string nav_sat(const nmea::Fix& fix) {
  const int count = std::clamp(fix.satellites_in_view, 0, static_cast<int>(nmea::max_satellites));
  const bool differential = solution_of(fix).differential;
  std::string p;
  put_u4(p, tow_ms(fix));
  put_u1(p, 1);  // version
  put_u1(p, static_cast<std::uint32_t>(count));
  put_zeros(p, 2);
  for (int i = 0; i < count; ++i) {
    const nmea::SatelliteInView& sat = fix.satellites[static_cast<std::size_t>(i)];
    std::uint32_t gnss_id = 0;
    int sv_id = sat.prn;
    if (sat.prn >= 33 && sat.prn <= 64) {
      gnss_id = 1;  // SBAS: NMEA 33..64 are PRN 120..151
      sv_id = sat.prn + 87;
    } else if (sat.prn >= 65 && sat.prn <= 96) {
      gnss_id = 6;  // GLONASS: slot = NMEA id - 64
      sv_id = sat.prn - 64;
    }
    const bool tracked = sat.snr_dbhz.has_value();
    const bool used = sat.used && fix.has_fix();
    // qualityInd: 7 code and carrier locked (used), 4 code locked, 1 searching.
    const std::uint32_t quality = used ? 7 : tracked ? 4 : 1;
    std::uint32_t flags = quality | (used ? 0x08u : 0u) | 0x10u;  // health 1: healthy
    if (used && differential) flags |= 0x40u;                     // diffCorr
    if (used) flags |= 0x100u | 0x800u;                           // orbitSource ephemeris, ephAvail
    put_u1(p, gnss_id);
    put_u1(p, static_cast<std::uint32_t>(sv_id));
    put_u1(p, static_cast<std::uint32_t>(sat.snr_dbhz.value_or(0)));
    put_i1(p, sat.elevation_deg);
    put_i2(p, sat.azimuth_deg);
    put_i2(p, 0);  // prRes
    put_u4(p, flags);
  }
  return p;
}

std::string nav_cov(const nmea::Fix& fix, const NavExtras& extras) {
  const bool ok = fix.has_fix();
  const auto sq = [](double v) { return static_cast<float>(v * v); };
  std::string p;
  put_u4(p, tow_ms(fix));
  put_u1(p, 0);  // version
  put_u1(p, ok ? 1u : 0u);  // posCovValid
  put_u1(p, ok ? 1u : 0u);  // velCovValid
  put_zeros(p, 9);
  for (const float v : {sq(fix.sigma_lat_m), 0.0f, 0.0f, sq(fix.sigma_lon_m), 0.0f, sq(fix.sigma_alt_m)}) {
    put_r4(p, ok ? v : 0.0f);
  }
  const float s2 = sq(extras.speed_sigma_mps);
  for (const float v : {s2, 0.0f, 0.0f, s2, 0.0f, s2}) put_r4(p, ok ? v : 0.0f);
  return p;
}

std::string nav_eoe(const nmea::Fix& fix) {
  std::string p;
  put_u4(p, tow_ms(fix));
  return p;
}

bool nav_encodes(MessageId id) {
  for (const MessageId m : {msg::nav_pvt, msg::nav_posllh, msg::nav_velned, msg::nav_status, msg::nav_sol,
                            msg::nav_posecef, msg::nav_velecef, msg::nav_dop, msg::nav_timeutc, msg::nav_timegps,
                            msg::nav_sat, msg::nav_cov, msg::nav_eoe}) {
    if (m == id) return true;
  }
  return false;
}

std::optional<std::string> nav_payload(MessageId id, const nmea::Fix& fix, const NavExtras& extras) {
  if (id == msg::nav_pvt) return nav_pvt(fix, extras);
  if (id == msg::nav_posllh) return nav_posllh(fix);
  if (id == msg::nav_velned) return nav_velned(fix, extras);
  if (id == msg::nav_status) return nav_status(fix, extras);
  if (id == msg::nav_sol) return nav_sol(fix, extras);
  if (id == msg::nav_posecef) return nav_posecef(fix);
  if (id == msg::nav_velecef) return nav_velecef(fix, extras);
  if (id == msg::nav_dop) return nav_dop(fix);
  if (id == msg::nav_timeutc) return nav_timeutc(fix);
  if (id == msg::nav_timegps) return nav_timegps(fix);
  if (id == msg::nav_sat) return nav_sat(fix);
  if (id == msg::nav_cov) return nav_cov(fix, extras);
  if (id == msg::nav_eoe) return nav_eoe(fix);
  return std::nullopt;
}

}  // namespace gpsemu::ubx
