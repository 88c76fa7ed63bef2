// The serial line budget (docs/design.md "Serial line budget"): what an 8N1 line at a given baud can
// carry, and whether a rate and an epoch size fit in it with a safety margin. Pure arithmetic, no
// I/O: the caller measures the epoch size (by formatting a worst-case epoch) and decides.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace gpsemu::transport {

/// The baud rates a serial output accepts (bits per second), slowest first: the standard termios
/// speeds from 4800 (NMEA 0183's own) to 921600.
inline constexpr std::array<int, 9> kStandardBauds = {4800,   9600,   19200,  38400, 57600,
                                                      115200, 230400, 460800, 921600};

/// A serial output's baud when the spec does not give one (bits per second): u-blox's default.
inline constexpr int kDefaultBaud = 9600;

/// Share of a line's capacity an emulator may plan to use (the rest absorbs epochs that run
/// longer than the measured worst case and a far end that is a little slow to read).
inline constexpr double kLineBudgetMargin = 0.9;

/// True when `baud_bps` is one of kStandardBauds.
[[nodiscard]] bool is_standard_baud(int baud_bps);

/// Bytes per second an 8N1 line carries at `baud_bps`: a start bit, 8 data bits and a stop bit,
/// so baud/10.
[[nodiscard]] constexpr double line_bytes_per_second(int baud_bps) { return baud_bps / 10.0; }

struct LineBudget {
  double needed_bytes_per_s = 0.0;  ///< epoch size x rate (bytes per second)
  double line_bytes_per_s = 0.0;    ///< what the line carries at its baud (bytes per second)
  double usable_bytes_per_s = 0.0;  ///< line_bytes_per_s x margin (bytes per second)
  bool fits = false;                ///< needed <= usable
  /// The slowest standard baud at which it would fit; empty when not even 921600 suffices.
  std::optional<int> fitting_baud;
};

/// Checks `epoch_bytes` (bytes) sent `rate_hz` times a second over an 8N1 line at `baud_bps`,
/// planning to use at most `margin` (0..1] of the line.
[[nodiscard]] LineBudget line_budget(int baud_bps, std::size_t epoch_bytes, double rate_hz,
                                     double margin = kLineBudgetMargin);

/// "4800, 9600, ..., 921600": for messages.
[[nodiscard]] std::string standard_bauds_text();

}  // namespace gpsemu::transport
