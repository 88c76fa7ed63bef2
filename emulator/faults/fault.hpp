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
#include "emulator/faults/kinds.hpp"
#include "emulator/model/enu.hpp"
#include "emulator/model/sky.hpp"
#include "emulator/model/time.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::faults {

/// Weeks a week-number rollover takes the date back (the 10-bit GPS week).
inline constexpr int kRolloverWeeks = 1024;

/// A C/N0 below this is not tracked (dB-Hz): a jammed satellite under it drops from the solution.
inline constexpr double kTrackingThresholdDbHz = 20.0;
/// The strongest jam (C/N0 drop at full strength, dB): `db`'s upper bound and `leave`'s largest drop.
inline constexpr double kMaxJamDb = 60.0;
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

/// A fault: the part every kind shares (when, for which receiver, where, its ramp) and its own
/// parameters, one type per kind (kinds.hpp).
struct Fault {
  FaultParams params;                 ///< the kind and its own parameters (kinds.hpp)
  double at_s = 0.0;                  ///< start, seconds after the first epoch (`at`)
  std::optional<double> duration_s;   ///< length in seconds (`duration`, or `end` - `at`); empty: to the end
  std::optional<int> receiver;        ///< fleet index it applies to; empty: every receiver
  // The ramp in and out: only the kinds whose catalogue row lists ramp_s and ramp_out_s (wrong,
  // degrade, jam, spoof) take them (make_fault refuses them elsewhere), so they stay 0 for the others.
  double ramp_s = 0.0;                ///< reaches full strength over this long (seconds)
  double ramp_out_s = 0.0;            ///< fades to nothing over this long after its end (seconds)
  // Triggers (docs/faults.md#triggers).
  std::optional<UtcNs> at_utc;        ///< starts at this UTC time (`at_utc`) in place of `at`
  std::optional<Area> where;          ///< active while the truth is inside (`where`), armed from `at`
  std::optional<double> disarm_s;     ///< where: no longer armed from this time (s; a replayed live clear)
  FaultOrigin origin;                 ///< the file and lines it came from, for start-up messages

  /// The kind: the index of `params`' alternative.
  [[nodiscard]] FaultKind kind() const { return kind_of(params); }
  /// Whether it is of kind `K` (a type of kinds.hpp).
  template <class K>
  [[nodiscard]] bool is() const {
    return std::holds_alternative<K>(params);
  }
  /// Its parameters as kind `K`, or null when it is of another kind.
  template <class K>
  [[nodiscard]] const K* as() const {
    return std::get_if<K>(&params);
  }

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
