// NAV-RELPOSNED (see relposned.hpp).
#include "emulator/ubx/relposned.hpp"

#include <algorithm>
#include <cmath>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/layouts.hpp"
#include "emulator/ubx/nav.hpp"

namespace gpsemu::ubx {
namespace {

constexpr std::size_t kPayloadBytes = 64;

/// Metres as whole centimetres and the 0.1 mm rest (-99..99), both with the value's sign.
struct CmAndHp {
  std::int32_t cm = 0;
  std::int32_t hp = 0;
};
CmAndHp split_cm(double m) {
  const double tenth_mm = std::clamp(std::round(m * 1e4), -2.0e11, 2.0e11);
  const auto total = static_cast<std::int64_t>(tenth_mm);
  return {static_cast<std::int32_t>(total / 100), static_cast<std::int32_t>(total % 100)};
}

std::uint32_t tenth_mm(double m) { return static_cast<std::uint32_t>(std::clamp(std::round(m * 1e4), 0.0, 4.0e9)); }
std::int32_t e5_deg(double deg) { return static_cast<std::int32_t>(std::lround(deg * 1e5)); }

}  // namespace

std::string nav_relposned(const nmea::Fix& fix, const RelPosNed& rel) {
  const bool fix_ok = fix.has_fix();
  const bool valid = fix_ok && rel.rel_pos_valid;
  static_assert(layout_bytes(layout::nav_relposned) == kPayloadBytes);
  PayloadWriter<layout::nav_relposned> w;
  w.set<"version">(1);
  w.set<"refStationId">(rel.ref_station_id);
  w.set<"iTOW">(gps_time(fix).tow_ms);
  const CmAndHp n = split_cm(valid ? rel.north_m : 0.0), e = split_cm(valid ? rel.east_m : 0.0),
                d = split_cm(valid ? rel.down_m : 0.0), len = split_cm(valid ? rel.length_m : 0.0);
  const bool heading = valid && rel.heading_valid;
  w.set<"relPosN">(n.cm);
  w.set<"relPosE">(e.cm);
  w.set<"relPosD">(d.cm);
  w.set<"relPosLength">(len.cm);
  w.set<"relPosHeading">(heading ? e5_deg(rel.heading_deg) : 0);
  w.set<"relPosHPN">(n.hp);
  w.set<"relPosHPE">(e.hp);
  w.set<"relPosHPD">(d.hp);
  w.set<"relPosHPLength">(len.hp);
  w.set<"accN">(valid ? tenth_mm(rel.acc_north_m) : 0);
  w.set<"accE">(valid ? tenth_mm(rel.acc_east_m) : 0);
  w.set<"accD">(valid ? tenth_mm(rel.acc_down_m) : 0);
  w.set<"accLength">(valid ? tenth_mm(rel.acc_length_m) : 0);
  w.set<"accHeading">(
      heading ? static_cast<std::uint32_t>(std::clamp(std::round(rel.acc_heading_deg * 1e5), 0.0, 1.8e7)) : 0);
  std::uint32_t flags = 0;
  if (fix_ok) flags |= 1u << 0;
  if (fix_ok && rel.diff_soln) flags |= 1u << 1;
  if (valid) flags |= 1u << 2;
  if (valid) flags |= static_cast<std::uint32_t>(rel.carrier) << 3;
  if (rel.is_moving) flags |= 1u << 5;
  if (fix_ok && rel.ref_pos_miss) flags |= 1u << 6;
  if (fix_ok && rel.ref_obs_miss) flags |= 1u << 7;
  if (heading) flags |= 1u << 8;
  w.set<"flags">(flags);
  return std::move(w).bytes();
}

RelPosNedFields read_relposned(const std::string& p) {
  RelPosNedFields f;
  if (p.size() != kPayloadBytes) return f;
  const auto i4 = [&p](std::size_t at) { return get_i4(p, at); };
  const auto i1 = [&p](std::size_t at) { return static_cast<std::int8_t>(p[at]); };
  f.version = static_cast<std::uint8_t>(p[0]);
  f.itow_ms = get_u4(p, 4);
  f.n_cm = i4(8);
  f.e_cm = i4(12);
  f.d_cm = i4(16);
  f.length_cm = i4(20);
  f.heading_1e5deg = i4(24);
  f.hp_n = i1(32);
  f.hp_e = i1(33);
  f.hp_d = i1(34);
  f.hp_length = i1(35);
  f.acc_n = get_u4(p, 36);
  f.acc_e = get_u4(p, 40);
  f.acc_d = get_u4(p, 44);
  f.acc_length = get_u4(p, 48);
  f.acc_heading_1e5deg = get_u4(p, 52);
  f.flags = get_u4(p, 60);
  return f;
}

}  // namespace gpsemu::ubx
