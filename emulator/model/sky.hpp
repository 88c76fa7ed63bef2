// A synthetic GPS sky: which satellites a receiver sees, where (elevation, azimuth) and how
// strongly (C/N0), moving slowly and smoothly, deterministic given the seed. Not an orbit
// propagator: each satellite follows a smooth track chosen so that the configured number is
// always in view, spread around the horizon (a good geometry, matching a small HDOP). Pure.
#pragma once

#include <array>
#include <cstdint>

#include "nmea/fix.hpp"

namespace gpsemu {

class Sky {
 public:
  /// `in_view` satellites (clamped to 1..32) with distinct GPS PRNs from 1..32, their
  /// tracks drawn from noise::Rng(seed, kSkyStream). Tracks: elevation el0 + A sin(2 pi t / P + phi)
  /// with el0 15..75 deg, A 4..12 deg, P 3..8 h (at most 0.5 deg a minute, like GPS); azimuth
  /// az0 + w t with az0 spread evenly around the horizon and |w| 0.2..0.5 deg a minute; C/N0
  /// 22 + 24 sin(elevation) dB-Hz plus a per-satellite offset (+-2) and a slow 10-minute wobble
  /// (+-2), rounded, so 20..50 dB-Hz.
  Sky(std::uint64_t seed, int in_view);

  [[nodiscard]] int in_view() const { return in_view_; }

  /// Writes the sky at `since_start_s` (seconds after the first epoch) into fix.satellites, sorted
  /// by PRN, and sets fix.satellites_in_view. Only the first `acquired` satellites of the
  /// acquisition order (a seeded permutation; a cold start acquires them one by one) are listed.
  /// The `used` highest (by elevation, ties by PRN) of those listed get `used = true`. No allocation.
  void fill(double since_start_s, int acquired, int used, nmea::Fix& fix) const;

  /// Stream of noise::Rng reserved for the sky (the noise models use 0..2).
  static constexpr std::uint64_t kSkyStream = 0x736b79;  // "sky"

 private:
  struct Track {
    int prn = 0;
    int acquisition_rank = 0;
    double el0_deg = 45.0, el_amp_deg = 0.0, el_period_s = 1.0, el_phase_rad = 0.0;
    double az0_deg = 0.0, az_rate_deg_per_s = 0.0;
    double snr_offset_db = 0.0, snr_phase_rad = 0.0;
  };
  std::array<Track, nmea::max_satellites> tracks_{};  // sorted by PRN
  int in_view_ = 0;
};

}  // namespace gpsemu
