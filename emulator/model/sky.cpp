#include "emulator/model/sky.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "emulator/model/noise/rng.hpp"

namespace gpsemu {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kGolden = 0.6180339887498949;  // low-discrepancy spread of base elevations
constexpr double kSnrWobblePeriodS = 600.0;
constexpr int kGpsPrns = 32;  // the sky is GPS only: PRNs 1..32

double elevation_deg(double el0, double amp, double period_s, double phase, double t_s) {
  return el0 + amp * std::sin(2.0 * kPi * t_s / period_s + phase);
}

}  // namespace

Sky::Sky(std::uint64_t seed, int in_view)
    : in_view_(std::clamp(in_view, 1, kGpsPrns)) {
  noise::Rng rng(seed, kSkyStream);
  // PRNs: a Fisher-Yates shuffle of 1..32; the first in_view are in view.
  std::array<int, kGpsPrns> prns{};
  for (std::size_t i = 0; i < prns.size(); ++i) prns[i] = static_cast<int>(i) + 1;
  for (std::size_t i = prns.size() - 1; i > 0; --i) {
    const auto j = static_cast<std::size_t>(rng.uniform() * static_cast<double>(i + 1));
    std::swap(prns[i], prns[std::min(j, i)]);
  }
  const double n = in_view_;
  const double az_start = 360.0 * rng.uniform();
  const double el_start = rng.uniform();
  for (int i = 0; i < in_view_; ++i) {
    Track& t = tracks_[static_cast<std::size_t>(i)];
    t.prn = prns[static_cast<std::size_t>(i)];
    t.az0_deg = std::fmod(az_start + 360.0 * (i + 0.8 * rng.uniform()) / n, 360.0);
    t.az_rate_deg_per_s = (rng.uniform() < 0.5 ? -1.0 : 1.0) * (0.2 + 0.3 * rng.uniform()) / 60.0;
    t.el0_deg = 15.0 + 60.0 * std::fmod(el_start + kGolden * i, 1.0);
    t.el_amp_deg = 4.0 + 8.0 * rng.uniform();
    t.el_period_s = 3600.0 * (3.0 + 5.0 * rng.uniform());
    t.el_phase_rad = 2.0 * kPi * rng.uniform();
    t.snr_offset_db = -2.0 + 4.0 * rng.uniform();
    t.snr_phase_rad = 2.0 * kPi * rng.uniform();
  }
  // Acquisition order: another shuffle, over the satellites in view.
  std::array<int, nmea::max_satellites> order{};
  for (int i = 0; i < in_view_; ++i) order[static_cast<std::size_t>(i)] = i;
  for (int i = in_view_ - 1; i > 0; --i) {
    const auto j = static_cast<int>(rng.uniform() * (i + 1));
    std::swap(order[static_cast<std::size_t>(i)], order[static_cast<std::size_t>(std::min(j, i))]);
  }
  for (int rank = 0; rank < in_view_; ++rank) {
    tracks_[static_cast<std::size_t>(order[static_cast<std::size_t>(rank)])].acquisition_rank = rank;
  }
  std::sort(tracks_.begin(), tracks_.begin() + in_view_, [](const Track& a, const Track& b) { return a.prn < b.prn; });
}

void Sky::fill(double since_start_s, int acquired, int used, nmea::Fix& fix) const {
  std::array<double, nmea::max_satellites> elevation{};
  int listed = 0;
  for (int i = 0; i < in_view_; ++i) {
    const Track& t = tracks_[static_cast<std::size_t>(i)];
    if (t.acquisition_rank >= acquired) continue;
    const double el = elevation_deg(t.el0_deg, t.el_amp_deg, t.el_period_s, t.el_phase_rad, since_start_s);
    double az = std::fmod(t.az0_deg + t.az_rate_deg_per_s * since_start_s, 360.0);
    if (az < 0.0) az += 360.0;
    const double snr = 22.0 + 24.0 * std::sin(el * kPi / 180.0) + t.snr_offset_db +
                       2.0 * std::sin(2.0 * kPi * since_start_s / kSnrWobblePeriodS + t.snr_phase_rad);
    nmea::SatelliteInView& out = fix.satellites[static_cast<std::size_t>(listed)];
    out.prn = t.prn;
    out.system = nmea::GnssSystem::gps;
    out.sv_id = t.prn;
    out.elevation_deg = static_cast<int>(std::lround(el));
    out.azimuth_deg = static_cast<int>(std::lround(az)) % 360;
    out.snr_dbhz = static_cast<int>(std::lround(snr));
    out.used = false;
    elevation[static_cast<std::size_t>(listed)] = el;
    ++listed;
  }
  fix.satellites_in_view = listed;
  // Used: the `used` highest; rank = how many are higher (ties: the lower PRN, listed first, wins).
  for (int i = 0; i < listed; ++i) {
    int higher = 0;
    for (int j = 0; j < listed; ++j) {
      const double ej = elevation[static_cast<std::size_t>(j)], ei = elevation[static_cast<std::size_t>(i)];
      if (ej > ei || (ej == ei && j < i)) ++higher;
    }
    fix.satellites[static_cast<std::size_t>(i)].used = higher < used;
  }
}

}  // namespace gpsemu
