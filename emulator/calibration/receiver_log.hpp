// A stationary receiver's NMEA log as calibration input: the fixes of its GGA sentences with their
// times, the speeds over ground the receiver reported (RMC, VTG), the log's epoch rate and
// coordinate resolution, and what was skipped (binary protocols, bad checksums, malformed
// sentences, no-fix epochs, repeated times), then the fixes as local East/North/Up metres about
// their mean position on the log's epoch grid (gaps left empty). A file is read in chunks: memory
// is the fixes (about 70 bytes each), not the file.
#pragma once

#include <array>
#include <optional>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/model/geo.hpp"
#include "nmea/parse.hpp"

namespace gpsemu::calibration {

/// What reading a log found and skipped.
struct LogCounts {
  nmea::StreamStats stream;          ///< sentences, bad checksums, malformed, binary bytes, comments
  std::uint64_t gga = 0;             ///< GGA sentences with a valid checksum
  std::uint64_t gga_malformed = 0;   ///< GGA that did not parse (fields)
  std::uint64_t gga_no_fix = 0;      ///< GGA with quality 0 or empty position / time / altitude
  std::uint64_t repeated_time = 0;   ///< fixes whose time does not advance (dropped)
  std::uint64_t missing_epochs = 0;  ///< grid epochs between the first and last fix without a fix
  std::uint64_t speed_reports = 0;   ///< speeds over ground read (active RMC, VTG)
};

struct LogFix {
  double time_s = 0.0;  ///< seconds since the first fix (midnight roll-over handled)
  Geodetic position;    ///< latitude, longitude (degrees), altitude above MSL (metres)
  std::optional<double> hdop;  ///< the HDOP the receiver stated with the fix, if any
};

/// A speed over ground the receiver stated, at the time of the latest fix before it.
struct SpeedReport {
  double time_s = 0.0;     ///< seconds since the first fix (0 before it)
  float speed_mps = 0.0f;  ///< metres per second
};

struct ReceiverLog {
  std::vector<LogFix> fixes;  ///< in time order, strictly increasing times
  /// The receiver's own speeds over ground: the active RMCs' when the log has any, else the VTGs'
  /// (one source, so an epoch with both counts once); empty when it states none.
  std::vector<SpeedReport> speeds;
  LogCounts counts;
  int minute_decimals = 0;    ///< most common decimals of minutes in the fixes' latitudes
  int alt_decimals = 1;       ///< most common decimals of the fixes' GGA altitudes (0..9)
};

/// Reads a log incrementally: feed bytes in any chunks (a sentence may straddle two), then finish.
class ReceiverLogReader {
 public:
  void feed(std::string_view bytes);
  /// The log read so far (the reader is spent).
  [[nodiscard]] ReceiverLog finish();

 private:
  void take(const nmea::Sentence& s);

  nmea::StreamReader stream_;
  ReceiverLog log_;
  std::vector<SpeedReport> vtg_speeds_;
  std::array<std::size_t, 10> decimals_{};      // fixes per minute decimals 0..9
  std::array<std::size_t, 10> alt_decimals_{};  // fixes per altitude decimals 0..9
  double first_tod_s_ = 0.0, prev_s_ = 0.0, day_offset_s_ = 0.0, prev_tod_s_ = 0.0;
};

/// Reads NMEA text (any bytes: binary protocols and junk are skipped and counted).
[[nodiscard]] ReceiverLog read_receiver_log(std::string_view bytes);
/// Reads a file in chunks of 1 MiB; throws std::runtime_error naming the path when it cannot be read.
[[nodiscard]] ReceiverLog read_receiver_log_file(const std::string& path);

/// The epoch rates the emulator offers (design: 1..50 whole, 0.5/0.25/0.2/0.1), nearest in ratio.
[[nodiscard]] double snap_rate_hz(double rate_hz);

/// Local ENU metres about a centre, one sample per epoch of the log's grid; NaN where the log has
/// no fix (a gap).
struct EnuSeries {
  std::array<std::vector<double>, 3> axis_m;  ///< east, north, up (metres); NaN in gaps
  Geodetic centre;            ///< mean position of the fixes (the frame's origin)
  double rate_hz = 1.0;       ///< the grid's rate (detected: median interval, snapped)
  int minute_decimals = 5;    ///< the log's coordinate resolution
  int alt_decimals = 1;       ///< the log's altitude resolution (decimals of metres)
  [[nodiscard]] std::size_t size() const { return axis_m[0].size(); }
  [[nodiscard]] double duration_s() const { return static_cast<double>(size()) / rate_hz; }
};

/// At most this many grid epochs are calibrated, whatever the memory (calibrate.hpp derives a
/// lower limit from the memory available).
inline constexpr std::size_t kMaxCalibrationEpochs = 10'000'000;

/// Puts the fixes on their grid: rate from the median interval between fixes, index
/// round((t - t0) * rate); a second fix on an index already taken counts as repeated. Fills
/// `log.counts.missing_epochs`. Throws std::invalid_argument when fewer than 16 fixes remain or
/// the fixes span `max_epochs` grid epochs or more (`why_limit` says where the limit comes from).
[[nodiscard]] EnuSeries to_enu_series(ReceiverLog& log, std::size_t max_epochs = kMaxCalibrationEpochs,
                                      std::string_view why_limit = "");

}  // namespace gpsemu::calibration
