// The serial line budget (docs/design.md "Serial line budget"), pure arithmetic: what an 8N1 line at a
// given baud carries, the standard bauds, and what a sentence set needs, measured on the widest
// epoch the formatters can write (one worst-case Fix). The start-up check that refuses a serial
// output too slow for its epochs (emulator/pipeline/serial_line_check) is built on it.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <span>
#include <string>

#include "nmea/fix.hpp"

namespace gpsemu::nmea {

/// The baud rates a serial line may run at (bits per second), slowest first: the standard termios
/// speeds from 4800 (NMEA 0183's own) to 921600.
inline constexpr std::array<int, 9> kStandardBauds = {4800,   9600,   19200,  38400, 57600,
                                                      115200, 230400, 460800, 921600};

/// A serial line's baud when none is given (bits per second): u-blox's default.
inline constexpr int kDefaultBaud = 9600;

/// Share of a line's capacity the emulator plans to use at start-up (the rest absorbs epochs that
/// run longer than the measured worst case and a far end that is a little slow to read).
inline constexpr double kLineBudgetMargin = 0.9;

/// True when `baud_bps` is one of kStandardBauds.
[[nodiscard]] bool is_standard_baud(int baud_bps);

/// "4800, 9600, ..., 921600": for messages.
[[nodiscard]] std::string standard_bauds_text();

/// Bytes per second an 8N1 line carries at `baud_bps`: a start bit, 8 data bits and a stop bit,
/// so baud/10.
[[nodiscard]] constexpr double line_bytes_per_second(int baud_bps) { return baud_bps / 10.0; }
/// Whole bytes a line at `baud_bps` (8N1) carries in `period`.
[[nodiscard]] constexpr std::size_t line_bytes_per_period(std::uint32_t baud_bps, std::chrono::nanoseconds period) {
  return static_cast<std::size_t>(static_cast<std::uint64_t>(baud_bps) * static_cast<std::uint64_t>(period.count()) /
                                  10'000'000'000ULL);
}

/// What a stream of epochs needs from a serial line (8N1: 10 bits on the wire per byte).
struct LineBudget {
  std::size_t bytes_per_epoch = 0;  ///< the longest epoch (bytes, CR LF included)
  double bytes_per_second = 0.0;    ///< bytes_per_epoch x rate (bytes per second)
  double min_baud = 0.0;            ///< bits per second the line needs: 10 x bytes_per_second
  /// True when a line of `baud_bps` carries every epoch within its period, using at most `margin`
  /// (0..1] of the line.
  [[nodiscard]] bool fits(double baud_bps, double margin = 1.0) const {
    return bytes_per_second <= baud_bps / 10.0 * margin;
  }
};

/// The budget of epochs of `bytes_per_epoch` bytes sent `rate_hz` times a second.
[[nodiscard]] LineBudget line_budget(std::size_t bytes_per_epoch, double rate_hz);

/// The widest epoch a receiver can write: every field at its widest realistic value (2099-12-31
/// 23:59:59.999, 89°59.99999' S, 179°59.99999' W, -12345.6 m altitude, -106.9 m geoid separation,
/// 500 m/s, course 359.99, HDOP/PDOP/VDOP 99.99, GST values 999.999 m, RTK float, 3-D, GGA's
/// differential age 999.9 s and station id 4095, as RTK corrections make them) with
/// `satellites_in_view` satellites in view (PRN 32, elevation 90, azimuth 359, SNR 99), the first
/// `satellites_used` used. Counts are clamped to 0..max_satellites and used <= in view.
[[nodiscard]] Fix widest_fix(int satellites_in_view, int satellites_used);

/// Satellites in view of one system: the widest epoch lists each system in its own GSV group and
/// GSA (NMEA 4.1), as a multi-GNSS receiver writes them.
struct SystemSatellites {
  GnssSystem system = GnssSystem::gps;
  int in_view = 0;
};

/// widest_fix() with the satellites of each of `systems` (in that order, at most max_satellites in
/// all), the first `satellites_used` of them used.
[[nodiscard]] Fix widest_fix(std::span<const SystemSatellites> systems, int satellites_used);

/// The line budget of options.sentences at `rate_hz` for the satellites of `systems`.
[[nodiscard]] LineBudget line_budget(const FormatOptions& options, std::span<const SystemSatellites> systems,
                                     int satellites_used, double rate_hz);

/// The line budget of options.sentences at `rate_hz`, measured by formatting
/// widest_fix(satellites_in_view, satellites_used) with options' talker, decimals and version.
[[nodiscard]] LineBudget line_budget(const FormatOptions& options, int satellites_in_view, int satellites_used,
                                     double rate_hz);

/// The smallest standard baud that carries `budget` within `margin` of the line; 0 when none does.
[[nodiscard]] int smallest_standard_baud(const LineBudget& budget, double margin = 1.0);

}  // namespace gpsemu::nmea
