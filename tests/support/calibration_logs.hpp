// Test support for calibration: a stationary receiver's NMEA log written with the project's own
// formatters, with the mess real logs have (comments, binary frames, bad checksums, malformed and
// no-fix GGA, repeated times, gaps), and the counts a reader should report for it.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "emulator/model/geo.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::test {

struct MessyLog {
  std::string text;
  std::uint64_t fixes = 0, no_fix = 0, gaps = 0, bad_checksum = 0, malformed_gga = 0, repeated = 0;
  std::uint64_t binary_frames = 0;
};

/// `epochs` epochs at `rate_hz` from 2024-05-01 12:00:00 UTC, a slow wander of about a metre
/// about `origin`, `minute_decimals` decimals of minutes. With `messy`: every 10th epoch has no
/// fix, every 17th is missing, every 13th is followed by a binary frame (UBX-like, with a '$'
/// inside), every 23rd by a copy with a bad checksum, epoch 5 by a malformed GGA and epoch 7 by
/// a repeat of itself.
inline MessyLog make_log(double rate_hz, int epochs, int minute_decimals, bool messy,
                         Geodetic origin = {47.5, 8.25, 400.0}) {
  MessyLog log;
  const LocalFrame frame(origin);
  nmea::FormatOptions f;
  f.minute_decimals = minute_decimals;
  f.time_decimals = 2;
  f.talker = "GN";
  log.text = "# Name: synthetic receiver\n# Notes: made by the test suite\n";
  const nmea::UtcTime start = std::chrono::sys_days{std::chrono::year{2024} / 5 / 1} + std::chrono::hours(12);
  for (int k = 0; k < epochs; ++k) {
    const double t = k / rate_hz;
    nmea::Fix fix;
    fix.time_utc = start + std::chrono::milliseconds(std::llround(1000.0 * t));
    const bool edge = k == 0 || k == epochs - 1;
    if (messy && !edge && k % 17 == 0) {
      ++log.gaps;
      continue;
    }
    if (!(messy && !edge && k % 10 == 0)) {
      const Geodetic g = frame.to_geodetic(
          {0.8 * std::sin(t / 40.0) + 0.3 * std::sin(t / 7.0), 0.5 * std::cos(t / 55.0), 0.2 * std::sin(t / 30.0)});
      fix.quality = nmea::FixQuality::gps;
      fix.dimension = nmea::FixDimension::three_d;
      fix.lat_deg = g.lat_deg;
      fix.lon_deg = g.lon_deg;
      fix.alt_msl_m = g.alt_m;
      fix.satellites_used = 9;
      fix.hdop = 0.9;
      ++log.fixes;
    } else {
      ++log.no_fix;
    }
    const std::string gga = nmea::format_gga(fix, f);
    log.text += nmea::format_rmc(fix, f) + gga;
    if (!messy) continue;
    if (k % 13 == 0) {
      log.text += std::string("\xb5\x62\x01\x07\x5c\x00$\x10\x00\xff\x80\x7f", 12) + "\r\n";
      ++log.binary_frames;
    }
    if (k % 23 == 0 && fix.has_fix()) {
      std::string bad = gga;
      bad[bad.size() - 4] = bad[bad.size() - 4] == '0' ? '1' : '0';  // first checksum digit
      log.text += bad;
      ++log.bad_checksum;
    }
    if (k == 5) {
      log.text += nmea::frame("GNGGA,120005.00,47x0.000,N,00815.000,E,1,09,0.9,400.0,M,0.0,M,,");
      ++log.malformed_gga;
    }
    if (k == 7 && fix.has_fix()) {
      log.text += gga;
      ++log.repeated;
    }
  }
  return log;
}

/// A clean log of a receiver whose error is the noise model `config` (seed `seed`): GGA at
/// `rate_hz` for `duration_s` from 2024-05-01 12:00:00 UTC at `minute_decimals`, about `origin`
/// plus `track(t)` (ENU metres, e.g. a circle; none = stationary). `constant_alt`: the altitude
/// field is the origin's, whatever the noise.
inline std::string model_log(const noise::NoiseConfig& config, std::uint64_t seed, double rate_hz, double duration_s,
                             int minute_decimals, bool constant_alt = false, Enu (*track)(double t_s) = nullptr,
                             Geodetic origin = {47.5, 8.25, 400.0}) {
  const LocalFrame frame(origin);
  const auto model = noise::make_noise_model(config, seed);
  nmea::FormatOptions f;
  f.minute_decimals = minute_decimals;
  f.time_decimals = 2;
  const nmea::UtcTime start = std::chrono::sys_days{std::chrono::year{2024} / 5 / 1} + std::chrono::hours(12);
  std::string text;
  const auto epochs = static_cast<long>(std::llround(duration_s * rate_hz));
  for (long k = 0; k < epochs; ++k) {
    const double t = static_cast<double>(k) / rate_hz;
    Enu e = model->offset_at(std::chrono::nanoseconds(std::llround(t * 1e9)));
    if (track) {
      const Enu p = track(t);
      e = {e.east_m + p.east_m, e.north_m + p.north_m, e.up_m + p.up_m};
    }
    const Geodetic g = frame.to_geodetic(e);
    nmea::Fix fix;
    fix.time_utc = start + std::chrono::milliseconds(std::llround(1000.0 * t));
    fix.quality = nmea::FixQuality::gps;
    fix.dimension = nmea::FixDimension::three_d;
    fix.lat_deg = g.lat_deg;
    fix.lon_deg = g.lon_deg;
    fix.alt_msl_m = constant_alt ? origin.alt_m : g.alt_m;
    fix.satellites_used = 9;
    fix.hdop = 0.9;
    text += nmea::format_gga(fix, f);
  }
  return text;
}

}  // namespace gpsemu::test
