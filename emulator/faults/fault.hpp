// A fault of the receiver channel as data (PX4's FailureInjector, ArduPilot SITL's SIM_GPS_*
// parameters): what goes wrong, when, for which receiver, with its parameters in named units.
// A scenario is a list of them (`--scenario FILE`, [[fault]] tables); fault_timeline.hpp applies
// them to each epoch's fix after the receiver model and before the encoders. docs/faults.md is the
// catalogue.
#pragma once

#include <array>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "emulator/faults/area.hpp"
#include "emulator/faults/catalogue.hpp"
#include "emulator/model/enu.hpp"
#include "emulator/model/sky.hpp"
#include "emulator/model/time.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::faults {

/// What a `time` fault does to the reported time.
enum class TimeFaultMode {
  jump,      ///< the reported time steps by jump_s (and stays off while the fault lasts)
  rollover,  ///< GPS week-number rollover as buggy firmware does it: the date 1024 weeks early
  leap_second,  ///< a leap second announced from the fault's start and inserted at the end of leap_day
};
/// Weeks a week-number rollover takes the date back (the 10-bit GPS week).
inline constexpr int kRolloverWeeks = 1024;

/// A C/N0 below this is not tracked (dB-Hz): a jammed satellite under it drops from the solution.
inline constexpr double kTrackingThresholdDbHz = 20.0;
/// Fewest satellites of a 3-D fix: below, a jammed or degraded receiver has no fix.
inline constexpr int kMinFixSatellites = 4;

/// Where a fault was written, for start-up messages (empty file: a live request or a --tee file).
struct FaultOrigin {
  std::string file;      ///< "scenario file jam.toml", "config file run.toml"
  int table_line = 0;    ///< the line of its [[fault]]
  std::vector<std::pair<std::string, int>> key_lines;  ///< each key's line
  /// "scenario file jam.toml:7: [[fault]]: " with `key`'s line (the table's when it has none);
  /// "" without a file.
  [[nodiscard]] std::string prefix(std::string_view key = {}) const;
};

struct Fault {
  FaultKind kind = FaultKind::outage;
  double at_s = 0.0;                  ///< start, seconds after the first epoch (`at`)
  std::optional<double> duration_s;   ///< length in seconds (`duration`, or `end` - `at`); empty: to the end
  double ramp_s = 0.0;                ///< jam, wrong, degrade: reaches full strength over this long (seconds)
  std::optional<int> receiver;        ///< fleet index it applies to; empty: every receiver
  Enu offset_m{};                     ///< jump, wrong: east_m, north_m, up_m
  std::optional<double> decay_s;      ///< jump: the step decays with this time constant (seconds); empty: stays
  nmea::FixQuality quality = nmea::FixQuality::gps;  ///< fix-quality: `quality`
  std::optional<int> satellites;      ///< degrade: at most this many satellites used
  std::optional<double> dop_k;        ///< degrade: DOP factor (default: from the satellites dropped)
  std::optional<double> noise_k;      ///< degrade: factor on the position error and sigmas (default: dop_k)
  double db = 0.0;                    ///< jam: C/N0 reduction at full strength (dB)
  std::vector<SkyMaskSector> mask;    ///< sky-mask: the sectors blocked (`mask`: a preset or FROM-TO:ELEV,...)
  std::string mask_name;              ///< sky-mask: `mask` as given (for logs)
  double speed_mps = 0.0;             ///< spoof: the position is dragged away at this speed (m/s)
  double bearing_deg = 0.0;           ///< spoof: towards this direction (degrees true)
  double time_drift_ms_per_s = 0.0;   ///< spoof: the reported time drifts this much a second (ms/s)
  bool detected = false;              ///< spoof: the receiver says so (NAV-STATUS spoofDetState 3, else 1)
  TimeFaultMode time_mode = TimeFaultMode::jump;  ///< time: `mode`
  double jump_s = 0.0;                ///< time: the step of a jump (seconds, whole milliseconds)
  /// time, mode leap-second: the UTC day at whose end the second is inserted (`leap_utc`, the
  /// inserted second itself: "2026-12-31T23:59:60Z")
  std::chrono::sys_days leap_day{};
  double silent_s = 2.0;              ///< reset: the receiver boots this long, writing nothing (seconds)
  double ttff_s = 26.0;               ///< reset: then a cold start, no fix for this long (seconds)
  // Triggers and the ramp out (docs/faults.md#triggers).
  std::optional<UtcNs> at_utc;        ///< starts at this UTC time (`at_utc`) in place of `at`
  std::optional<Area> where;          ///< active while the truth is inside (`where`), armed from `at`
  std::optional<double> disarm_s;     ///< where: no longer armed from this time (s; a replayed live clear)
  double ramp_out_s = 0.0;            ///< jam, wrong, degrade: fades to nothing over this long after its end (s)
  // Byte-level faults.
  double rate = 0.0;                  ///< garble: fraction of sentences and frames hit (0..1)
  double delay_ms = 0.0;              ///< latency: the bytes leave this much after the epoch's deadline (ms)
  double jitter_ms = 0.0;             ///< latency: plus a uniform draw in [0, jitter_ms) each epoch (ms)
  FaultOrigin origin;                 ///< the file and lines it came from, for start-up messages

  /// Whether epoch time `since_s` (seconds after the first epoch) is inside the fault.
  /// Compared in whole nanoseconds, so 0.1 + 0.2 s ends at the epoch of 0.3 s.
  [[nodiscard]] bool active_at(double since_s) const {
    const auto ns = [](double s) { return std::llround(s * 1e9); };
    return ns(since_s) >= ns(at_s) && (!duration_s || ns(since_s) < ns(at_s + *duration_s));
  }
  /// 0..1: how far the ramp is at `since_s` (1 without a ramp).
  [[nodiscard]] double strength_at(double since_s) const;
  /// "jam db=25 ramp_s=5 at 10 s for 20 s, receiver 0": for logs and the summary.
  [[nodiscard]] std::string describe() const;
  /// "jam db=25 ramp_s=5": the kind and its parameters.
  [[nodiscard]] std::string parameters() const;
};

/// One key of a [[fault]] table (or a control message): a number or a string.
using FaultValue = std::variant<double, std::string>;
using FaultKeys = std::vector<std::pair<std::string, FaultValue>>;

/// A fault from its keys: `kind` (required), `at`, `duration` or `end`, `receiver` (index or
/// "all"), and the kind's own parameters (catalogue.hpp). Throws std::invalid_argument naming the
/// key ("db: ...") for an unknown key, a key the kind does not take, or a value out of range;
/// `source` says which common keys the message lists.
[[nodiscard]] Fault make_fault(const FaultKeys& keys, FaultSource source = FaultSource::scenario);

}  // namespace gpsemu::faults
