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

constexpr double kNodeS = 60.0;
// Azimuth/elevation (and with them the satellites used and the DOPs) are computed every this many
// GPS seconds and interpolated linearly between (docs/performance.md: 10 s would take a quarter
// off a --fast default epoch; a satellite moves at most ~0.01 degree a second).
constexpr std::int64_t kAzElStepS = 1;          // orbit nodes a minute apart (cubic: well under a metre)
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
      receiver_geodetic_{receiver.lat_deg, receiver.lon_deg, receiver.alt_m},
      receiver_ecef_(sky::to_ecef(receiver.lat_deg, receiver.lon_deg, receiver.alt_m)) {
  const auto& sats = orbits_->satellites();
  noise::Rng rng(options.seed, kSkyStream);
  cn0_offset_db_.resize(sats.size());
  acquisition_rank_.resize(sats.size());
  for (std::size_t i = 0; i < sats.size(); ++i) {
    cn0_offset_db_[i] = static_cast<float>(-2.0 + 4.0 * rng.uniform());
    acquisition_rank_[i] = static_cast<float>(rng.uniform());
    if (options.profile.systems.contains(sats[i].system)) tracked_.push_back(i);
  }
  // Listed in NMEA order: by system, then number.
  std::stable_sort(tracked_.begin(), tracked_.end(), [&](std::size_t a, std::size_t b) {
    return std::pair{system_rank(sats[a].system), sats[a].sv_id} < std::pair{system_rank(sats[b].system), sats[b].sv_id};
  });
  const double lat = receiver.lat_deg * kPi / 180.0, lon = receiver.lon_deg * kPi / 180.0;
  up_ = {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
  nodes_.resize(tracked_.size());
  azel0_.resize(tracked_.size());
  azel1_.resize(tracked_.size());
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
  // Four nodes around t: base-1, base, base+1, base+2, with base = floor(t / node).
  const auto base = static_cast<std::int64_t>(std::floor(t / kNodeS));
  if (base != node_base_) {
    // No nodes yet (INT64_MIN): every node computed (shift 0), without overflowing the subtraction.
    const std::int64_t shift = node_base_ == INT64_MIN ? 0 : base - node_base_;
    for (std::size_t j = 0; j < tracked_.size(); ++j) {
      auto& n = nodes_[j];
      if (shift > 0 && shift < 4) {
        for (int i = 0; i + shift < 4; ++i) n[static_cast<std::size_t>(i)] = n[static_cast<std::size_t>(i + shift)];
      }
      for (int i = 0; i < 4; ++i) {
        if (shift > 0 && shift < 4 && i < 4 - shift) continue;
        n[static_cast<std::size_t>(i)] = orbits_->position(tracked_[j], (static_cast<double>(base) + i - 1) * kNodeS);
      }
    }
    node_base_ = base;
  }
  const auto& n = nodes_[k];
  if (!n[0] || !n[1] || !n[2] || !n[3]) return std::nullopt;
  // Cubic Lagrange through nodes at x = -1, 0, 1, 2 (units of kNodeS).
  const double x = t / kNodeS - static_cast<double>(base);
  const double w0 = -x * (x - 1) * (x - 2) / 6.0, w1 = (x + 1) * (x - 1) * (x - 2) / 2.0;
  const double w2 = -(x + 1) * x * (x - 2) / 2.0, w3 = (x + 1) * x * (x - 1) / 6.0;
  return sky::Ecef{w0 * n[0]->x_m + w1 * n[1]->x_m + w2 * n[2]->x_m + w3 * n[3]->x_m,
                   w0 * n[0]->y_m + w1 * n[1]->y_m + w2 * n[2]->y_m + w3 * n[3]->y_m,
                   w0 * n[0]->z_m + w1 * n[1]->z_m + w2 * n[2]->z_m + w3 * n[3]->z_m};
}

void Sky::snapshot(std::int64_t second, std::vector<std::array<float, 2>>& azel) {
  const double t = orbits_->map_time(static_cast<double>(second));
  for (std::size_t k = 0; k < tracked_.size(); ++k) {
    azel[k] = {0.0f, -100.0f};
    const auto p = position(k, t);
    if (!p) continue;
    // Below the horizon (the line of sight points down): no need for RTKLIB's azimuth/elevation.
    const double up = (p->x_m - receiver_ecef_.x_m) * up_[0] + (p->y_m - receiver_ecef_.y_m) * up_[1] +
                      (p->z_m - receiver_ecef_.z_m) * up_[2];
    if (up < 0.0) {
      azel[k] = {0.0f, -1.0f};
      continue;
    }
    const sky::AzEl a = sky::azimuth_elevation(receiver_geodetic_, receiver_ecef_, *p);
    azel[k] = {static_cast<float>(a.azimuth_deg), static_cast<float>(a.elevation_deg)};
  }
}

void Sky::advance_to(std::int64_t second) {
  if (second == second_) return;
  if (second == second_ + kAzElStepS) {
    std::swap(azel0_, azel1_);
  } else {
    snapshot(second, azel0_);
  }
  snapshot(second + kAzElStepS, azel1_);
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
    std::array<sky::UsedSatellite, nmea::max_satellites> u{};
    std::size_t m = 0;
    for (std::size_t k = 0; k < usable.size(); ++k) {
      if (k == skip) continue;
      const Entry& e = entries_[usable[k]];
      u[m++] = {e.az0, e.el0, orbits_->satellites()[tracked_[e.sat]].system};
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
    const sky::ReceiverProfile& p = options_.profile;
    entries_.clear();
    for (std::size_t k = 0; k < tracked_.size(); ++k) {
      const float el = azel0_[k][1], az = azel0_[k][0];
      if (el <= 0.0f || azel1_[k][1] < -90.0f || obstructed(az, el)) continue;
      const std::size_t s = tracked_[k];
      if (acquisition_rank_[s] >= tracking.acquired_fraction) continue;
      Entry e;
      e.sat = static_cast<std::uint16_t>(k);
      e.az0 = az;
      e.el0 = el;
      e.az1 = azel1_[k][0];
      e.el1 = azel1_[k][1];
      const double cn0 = 28.0 + 20.0 * std::sin(el * kPi / 180.0) + cn0_offset_db_[s] -
                         (sats[s].system == nmea::GnssSystem::sbas ? 6.0 : 0.0);
      e.cn0 = static_cast<std::uint8_t>(std::clamp(std::lround(cn0), 0L, 99L));
      e.usable = el >= p.elevation_mask_deg && e.cn0 >= p.cn0_threshold_dbhz;
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
    std::array<sky::UsedSatellite, nmea::max_satellites> used{};
    used_ = 0;
    for (const Entry& e : entries_) {
      if (e.usable) used[static_cast<std::size_t>(used_++)] = {e.az0, e.el0, sats[tracked_[e.sat]].system};
    }
    dops_ = sky::multi_clock_dops(std::span(used.data(), static_cast<std::size_t>(used_)));
  }
  // Write the entries, azimuth and elevation interpolated within the second.
  const auto f = static_cast<float>((gps - static_cast<double>(second)) / kAzElStepS);
  const auto& sats = orbits_->satellites();
  int n = 0;
  for (const Entry& e : entries_) {
    nmea::SatelliteInView& out = fix.satellites[static_cast<std::size_t>(n++)];
    const sky::SatelliteId& id = sats[tracked_[e.sat]];
    out.system = id.system;
    out.sv_id = id.sv_id;
    out.prn = nmea_id(id);
    // Both non-negative: rounding is adding a half and truncating.
    out.elevation_deg = static_cast<int>(std::max(0.0f, e.el0 + f * (e.el1 - e.el0)) + 0.5f);
    out.azimuth_deg = static_cast<int>(lerp_azimuth(e.az0, e.az1, f) + 0.5f) % 360;
    out.snr_dbhz = e.cn0;
    out.used = e.usable;
  }
  fix.satellites_in_view = n;
  return {n, used_, dops_};
}

}  // namespace gpsemu
