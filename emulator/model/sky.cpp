#include "emulator/model/sky.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "emulator/model/noise/rng.hpp"

namespace gpsemu {
namespace {

// Orbit nodes (RTKLIB's position and velocity) this far apart in time, cubic Hermite between:
// within ~20 m of RTKLIB's own positions for a medium orbit (h^4/384 x r w^4; checked in
// tests/unit/model/sky_test.cpp), 0.0001 degree as seen from the ground. RTKLIB's broadcast
// orbits cost 3-5 us a call (GLONASS integrates from its reference time), so a minute apart
// they were most of a --fast epoch.
constexpr double kNodeS = 600.0;
// Azimuth/elevation (and with them the satellites used and the DOPs) are computed every this many
// GPS seconds and interpolated linearly between (a satellite moves at most ~0.015 degree a second).
constexpr std::int64_t kAzElStepS = 1;
// No GNSS satellite's elevation changes faster than this as seen from the ground (a medium orbit
// overhead: ~4.4 km/s across ~19 000 km is 0.013 degree/s): one further below the horizon than
// this rate covers is not looked at again until it could have risen.
constexpr double kMaxElevationRateDegPerS = 0.02;
constexpr std::uint64_t kSkyStream = 0x736b79;  // "sky": the noise models use streams 0..2
constexpr double kPi = std::numbers::pi;

/// System order of NMEA output (GP, GL, GA, GB, GQ; SBAS with GPS).
int system_rank(nmea::GnssSystem s) {
  switch (s) {
    case nmea::GnssSystem::gps: return 0;
    case nmea::GnssSystem::sbas: return 1;
    case nmea::GnssSystem::glonass: return 2;
    case nmea::GnssSystem::galileo: return 3;
    case nmea::GnssSystem::beidou: return 4;
    case nmea::GnssSystem::qzss: return 5;
  }
  return 6;
}

/// NMEA 4.11 satellite ID of a satellite (u-blox's numbering in NMEA 4.11 mode, each system under
/// its own GSV talker): GPS 1-32, SBAS 33-64 (PRN - 87), GLONASS 65-96 (slot + 64), Galileo 1-36,
/// BeiDou 1-63, QZSS 1-10.
int nmea_id(const sky::SatelliteId& id) {
  switch (id.system) {
    case nmea::GnssSystem::sbas: return id.sv_id - 87;
    case nmea::GnssSystem::glonass: return id.sv_id + 64;
    default: return id.sv_id;
  }
}

double parse_degrees(std::string_view text, std::string_view what) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc{} || end != text.data() + text.size() || !std::isfinite(v)) {
    throw std::invalid_argument("sky-mask: '" + std::string(text) + "' is not a number of degrees (" + std::string(what) + ")");
  }
  return v;
}

/// Linear interpolation of an azimuth across north.
float lerp_azimuth(float a0, float a1, float f) {
  float d = a1 - a0;
  if (d > 180.0f) d -= 360.0f;
  if (d < -180.0f) d += 360.0f;
  float a = a0 + f * d;
  if (a < 0.0f) a += 360.0f;
  if (a >= 360.0f) a -= 360.0f;
  return a;
}

}  // namespace

std::vector<SkyMaskSector> parse_sky_mask(std::string_view text) {
  if (text == "open" || text.empty()) return {};
  if (text == "urban-canyon") {
    // A street running north-south between buildings: low along the street, 45 degrees across.
    return {{20.0, 160.0, 45.0}, {200.0, 340.0, 45.0}, {340.0, 20.0, 10.0}, {160.0, 200.0, 10.0}};
  }
  std::vector<SkyMaskSector> sectors;
  while (!text.empty()) {
    const std::size_t comma = text.find(',');
    const std::string_view part = text.substr(0, comma);
    text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
    const std::size_t dash = part.find('-', 1);
    const std::size_t colon = part.find(':');
    if (dash == std::string_view::npos || colon == std::string_view::npos || colon < dash) {
      throw std::invalid_argument("sky-mask: '" + std::string(part) +
                                  "' is not FROM-TO:ELEVATION (degrees), 'urban-canyon' or 'open'");
    }
    SkyMaskSector s;
    s.from_azimuth_deg = parse_degrees(part.substr(0, dash), "azimuth from");
    s.to_azimuth_deg = parse_degrees(part.substr(dash + 1, colon - dash - 1), "azimuth to");
    s.min_elevation_deg = parse_degrees(part.substr(colon + 1), "elevation");
    if (s.from_azimuth_deg < 0 || s.from_azimuth_deg > 360 || s.to_azimuth_deg < 0 || s.to_azimuth_deg > 360 ||
        s.min_elevation_deg < 0 || s.min_elevation_deg > 90) {
      throw std::invalid_argument("sky-mask: '" + std::string(part) + "': azimuths 0..360, elevation 0..90 degrees");
    }
    sectors.push_back(s);
  }
  return sectors;
}

double gps_seconds_of(UtcNs t) {
  return std::chrono::duration<double>(t.time_since_epoch()).count() - 315964800.0 + 18.0;
}

Sky::Sky(const SkyOptions& options, const Geodetic& receiver)
    : orbits_(options.orbits ? options.orbits : sky::Orbits::embedded_default()),
      options_(options),
      receiver_ecef_(sky::to_ecef(receiver.lat_deg, receiver.lon_deg, receiver.alt_m)) {
  const auto& sats = orbits_->satellites();
  noise::Rng rng(options.seed, kSkyStream);
  cn0_offset_db_.resize(sats.size());
  acquisition_rank_.resize(sats.size());
  for (std::size_t i = 0; i < sats.size(); ++i) {
    cn0_offset_db_[i] = static_cast<float>(-2.0 + 4.0 * rng.uniform());
    acquisition_rank_[i] = static_cast<float>(rng.uniform());
    if (options.tracking.systems.contains(sats[i].system)) tracked_.push_back(i);
  }
  // Listed in NMEA order: by system, then number.
  std::stable_sort(tracked_.begin(), tracked_.end(), [&](std::size_t a, std::size_t b) {
    return std::pair{system_rank(sats[a].system), sats[a].sv_id} < std::pair{system_rank(sats[b].system), sats[b].sv_id};
  });
  const double lat = receiver.lat_deg * kPi / 180.0, lon = receiver.lon_deg * kPi / 180.0;
  // RTKLIB's xyz2enu axes.
  east_ = {-std::sin(lon), std::cos(lon), 0.0};
  north_ = {-std::sin(lat) * std::cos(lon), -std::sin(lat) * std::sin(lon), std::cos(lat)};
  up_ = {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
  nodes_.resize(tracked_.size());
  look0_.resize(tracked_.size());
  look1_.resize(tracked_.size());
  hidden_until_.assign(tracked_.size(), INT64_MIN);
}

bool Sky::obstructed(double az, double el) const {
  for (const SkyMaskSector& s : options_.obstruction) {
    const bool inside = s.from_azimuth_deg <= s.to_azimuth_deg ? (az >= s.from_azimuth_deg && az < s.to_azimuth_deg)
                                                               : (az >= s.from_azimuth_deg || az < s.to_azimuth_deg);
    if (inside && el < s.min_elevation_deg) return true;
  }
  return false;
}

std::optional<sky::Ecef> Sky::position(std::size_t k, double t) {
  // The two nodes around t: base and base + 1, with base = floor(t / node).
  const auto base = static_cast<std::int64_t>(std::floor(t / kNodeS));
  if (base != node_base_) {
    // One node on: the later one becomes the earlier. No nodes yet (INT64_MIN): both computed.
    const bool next = node_base_ != INT64_MIN && base == node_base_ + 1;
    for (std::size_t j = 0; j < tracked_.size(); ++j) {
      auto& n = nodes_[j];
      n[0] = next ? n[1] : orbits_->motion(tracked_[j], static_cast<double>(base) * kNodeS);
      n[1] = orbits_->motion(tracked_[j], static_cast<double>(base + 1) * kNodeS);
    }
    node_base_ = base;
  }
  const auto& n = nodes_[k];
  if (!n[0] || !n[1]) return std::nullopt;
  // Cubic Hermite on [0, 1] (units of kNodeS) from the positions and velocities at both ends.
  const double x = t / kNodeS - static_cast<double>(base);
  const double x2 = x * x, x3 = x2 * x;
  const double h00 = 2 * x3 - 3 * x2 + 1, h10 = (x3 - 2 * x2 + x) * kNodeS;
  const double h01 = -2 * x3 + 3 * x2, h11 = (x3 - x2) * kNodeS;
  const sky::EcefMotion& a = *n[0];
  const sky::EcefMotion& b = *n[1];
  return sky::Ecef{h00 * a.position.x_m + h10 * a.vx_mps + h01 * b.position.x_m + h11 * b.vx_mps,
                   h00 * a.position.y_m + h10 * a.vy_mps + h01 * b.position.y_m + h11 * b.vy_mps,
                   h00 * a.position.z_m + h10 * a.vz_mps + h01 * b.position.z_m + h11 * b.vz_mps};
}

void Sky::snapshot(std::int64_t second, std::vector<Look>& looks) {
  const double t = orbits_->map_time(static_cast<double>(second));
  // The skipping below assumes the satellites moved one second since the last snapshot: after a
  // jump (a new start, the day's wrap) every satellite is looked at again.
  if (std::fabs(t - last_mapped_ - 1.0) > 1e-3) std::fill(hidden_until_.begin(), hidden_until_.end(), INT64_MIN);
  last_mapped_ = t;
  constexpr double deg = 180.0 / kPi;
  for (std::size_t k = 0; k < tracked_.size(); ++k) {
    Look& look = looks[k];
    if (second < hidden_until_[k]) {
      look = {0.0f, -1.0f, {}};
      continue;
    }
    look = {0.0f, -100.0f, {}};
    const auto p = position(k, t);
    if (!p) continue;
    // The line of sight in the receiver's east-north-up axes (RTKLIB's geodist + satazel, with the
    // axes computed once).
    const double dx = p->x_m - receiver_ecef_.x_m, dy = p->y_m - receiver_ecef_.y_m, dz = p->z_m - receiver_ecef_.z_m;
    const double range = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double e = (dx * east_[0] + dy * east_[1]) / range;
    const double n = (dx * north_[0] + dy * north_[1] + dz * north_[2]) / range;
    const double u = (dx * up_[0] + dy * up_[1] + dz * up_[2]) / range;
    if (u < 0.0) {
      // Below the horizon: not listed; not looked at again until it could have risen.
      const double below_deg = -std::asin(u) * deg;
      look = {0.0f, -1.0f, {}};
      if (below_deg > 2.0) hidden_until_[k] = second + static_cast<std::int64_t>((below_deg - 1.0) / kMaxElevationRateDegPerS);
      continue;
    }
    double az = e * e + n * n < 1e-12 ? 0.0 : std::atan2(e, n) * deg;
    if (az < 0.0) az += 360.0;
    if (az >= 360.0) az -= 360.0;
    look = {static_cast<float>(az), static_cast<float>(std::asin(u) * deg), {e, n, u, nmea::GnssSystem::gps}};
  }
}

void Sky::advance_to(std::int64_t second) {
  if (second == second_) return;
  if (second == second_ + kAzElStepS) {
    std::swap(look0_, look1_);
  } else {
    snapshot(second, look0_);
  }
  snapshot(second + kAzElStepS, look1_);
  second_ = second;
}

int Sky::clock_of(const Entry& e) const {
  switch (orbits_->satellites()[tracked_[e.sat]].system) {
    case nmea::GnssSystem::glonass: return 1;
    case nmea::GnssSystem::galileo: return 2;
    case nmea::GnssSystem::beidou: return 3;
    default: return 0;
  }
}

void Sky::select_used(int limit) {
  std::vector<std::size_t> usable;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (entries_[i].usable) usable.push_back(i);
  }
  if (static_cast<int>(usable.size()) <= limit) return;
  for (Entry& e : entries_) e.usable = false;
  if (limit <= 0) return;
  // Few satellites: one system's, so no clock is spent on a second (the system with the most).
  if (limit <= 8) {
    std::array<int, 4> per_clock{};
    for (const std::size_t i : usable) ++per_clock[static_cast<std::size_t>(clock_of(entries_[i]))];
    const auto best = static_cast<int>(std::max_element(per_clock.begin(), per_clock.end()) - per_clock.begin());
    if (per_clock[static_cast<std::size_t>(best)] >= limit) {
      std::erase_if(usable, [&](std::size_t i) { return clock_of(entries_[i]) != best; });
    }
  }
  // A geometry a receiver would choose: drop, one at a time, the satellite whose loss raises the
  // PDOP least, until `limit` remain (greedy; only when the model's channels or --satellites cap).
  const auto pdop_without = [&](std::size_t skip) {
    std::array<sky::LineOfSight, nmea::max_satellites> u{};
    std::size_t m = 0;
    for (std::size_t k = 0; k < usable.size(); ++k) {
      if (k != skip) u[m++] = entries_[usable[k]].line;
    }
    const sky::Dops d = sky::multi_clock_dops(std::span(u.data(), m));
    return d.valid() ? d.pdop : 1e9;
  };
  while (static_cast<int>(usable.size()) > limit) {
    std::size_t drop = 0;
    double best_pdop = 2e9;
    for (std::size_t k = 0; k < usable.size(); ++k) {
      const double p = pdop_without(k);
      if (p < best_pdop) best_pdop = p, drop = k;
    }
    usable.erase(usable.begin() + static_cast<std::ptrdiff_t>(drop));
  }
  for (const std::size_t i : usable) entries_[i].usable = true;
}

void Sky::write_entry(const Entry& e, float f, nmea::SatelliteInView& out) const {
  const sky::SatelliteId& id = orbits_->satellites()[tracked_[e.sat]];
  out.system = id.system;
  out.sv_id = id.sv_id;
  out.prn = nmea_id(id);
  // Both non-negative: rounding is adding a half and truncating.
  out.elevation_deg = static_cast<int>(std::max(0.0f, e.el0 + f * (e.el1 - e.el0)) + 0.5f);
  out.azimuth_deg = static_cast<int>(lerp_azimuth(e.az0, e.az1, f) + 0.5f) % 360;
  out.snr_dbhz = e.cn0;
  out.used = e.usable;
}

SkyState Sky::fill(UtcNs t, const Tracking& tracking, nmea::Fix& fix) {
  const double gps = gps_seconds_of(t);
  const auto second = static_cast<std::int64_t>(std::floor(gps / kAzElStepS)) * kAzElStepS;
  const bool new_second = second != second_;
  advance_to(second);
  const bool same_tracking = tracking.acquired_fraction == tracking_.acquired_fraction &&
                             tracking.solving == tracking_.solving && tracking.max_used == tracking_.max_used;
  if (new_second || !same_tracking || entries_.empty()) {
    tracking_ = tracking;
    // Listed: above the horizon, not obstructed, acquired; within the channels (highest first).
    const auto& sats = orbits_->satellites();
    const sky::Tracking& p = options_.tracking;
    entries_.clear();
    for (std::size_t k = 0; k < tracked_.size(); ++k) {
      const Look& look = look0_[k];
      if (look.el <= 0.0f || look1_[k].el < -90.0f || obstructed(look.az, look.el)) continue;
      const std::size_t s = tracked_[k];
      if (acquisition_rank_[s] >= tracking.acquired_fraction) continue;
      Entry e;
      e.sat = static_cast<std::uint16_t>(k);
      e.az0 = look.az;
      e.el0 = look.el;
      e.az1 = look1_[k].az;
      e.el1 = look1_[k].el;
      e.line = look.line;
      e.line.system = sats[s].system;
      // C/N0 by elevation (the line of sight's up component is sin(elevation)).
      const double cn0 = 28.0 + 20.0 * look.line.up + cn0_offset_db_[s] -
                         (sats[s].system == nmea::GnssSystem::sbas ? 6.0 : 0.0);
      e.cn0 = static_cast<std::uint8_t>(std::clamp(std::lround(cn0), 0L, 99L));
      e.usable = look.el >= p.elevation_mask_deg && e.cn0 >= p.cn0_threshold_dbhz;
      entries_.push_back(e);
    }
    // Channels and the Fix's capacity: keep the highest.
    const int per_sat = p.dual_band ? 2 : 1;
    const std::size_t cap = std::min<std::size_t>(nmea::max_satellites, static_cast<std::size_t>(p.channels / per_sat));
    if (entries_.size() > cap) {
      std::vector<Entry> by_el = entries_;
      std::nth_element(by_el.begin(), by_el.begin() + static_cast<std::ptrdiff_t>(cap) - 1, by_el.end(),
                       [](const Entry& a, const Entry& b) { return a.el0 > b.el0; });
      const float cut = by_el[cap - 1].el0;
      std::size_t kept = 0;
      std::erase_if(entries_, [&](const Entry& e) { return e.el0 < cut || (e.el0 == cut && kept++ >= cap); });
      if (entries_.size() > cap) entries_.resize(cap);
    }
    // Used: the usable ones, at most max_used; none when not solving.
    int limit = tracking.solving ? tracking.max_used : 0;
    if (options_.max_used) limit = std::min(limit, *options_.max_used);
    select_used(limit);
    std::array<sky::LineOfSight, nmea::max_satellites> used{};
    used_ = 0;
    for (const Entry& e : entries_) {
      if (e.usable) used[static_cast<std::size_t>(used_++)] = e.line;
    }
    dops_ = sky::multi_clock_dops(std::span(used.data(), static_cast<std::size_t>(used_)));
    // What each entry writes all second: the integer degrees of the interpolation at its start.
    // Interpolation is monotone within the second, so when both ends round alike (and the azimuth
    // does not cross north) every moment does; the others ("moving") are interpolated each epoch.
    written_.resize(entries_.size());
    moving_.clear();
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      const Entry& e = entries_[i];
      write_entry(e, 0.0f, written_[i]);
      nmea::SatelliteInView end;
      write_entry(e, 1.0f, end);
      float d = e.az1 - e.az0;
      if (d > 180.0f) d -= 360.0f;
      if (d < -180.0f) d += 360.0f;
      const float az_end = e.az0 + d;
      if (end.elevation_deg != written_[i].elevation_deg || end.azimuth_deg != written_[i].azimuth_deg ||
          az_end < 0.0f || az_end >= 360.0f) {
        moving_.push_back(static_cast<std::uint8_t>(i));
      }
    }
  }
  // Write the entries, the moving ones' azimuth and elevation interpolated within the second.
  const auto n = static_cast<int>(entries_.size());
  std::copy(written_.begin(), written_.end(), fix.satellites.begin());
  if (!moving_.empty()) {
    const auto f = static_cast<float>((gps - static_cast<double>(second)) / kAzElStepS);
    for (const std::uint8_t i : moving_) write_entry(entries_[i], f, fix.satellites[i]);
  }
  fix.satellites_in_view = n;
  return {n, used_, dops_};
}

}  // namespace gpsemu
