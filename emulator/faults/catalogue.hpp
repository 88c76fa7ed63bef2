// The fault catalogue as one table (docs/faults.md, "The catalogue"): each kind's name and the
// parameters it takes, each parameter with its unit and range. The key parser (fault.cpp), the
// control socket's error messages and `gpsemu ctl`'s flags and help all read this table, so a new
// parameter is one row here (its field in the kind's struct, kinds.hpp, and its parse_key() in
// fault.cpp). FaultKind is the index of the kind's alternative in FaultParams (kinds.hpp).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gpsemu::faults {

/// The catalogue, in the order docs/faults.md lists it.
enum class FaultKind {
  outage,       ///< no satellites, no fix
  freeze,       ///< the last fix repeated with new times (PX4's "stuck")
  jump,         ///< a position step, staying or decaying (multipath, a bad fix)
  wrong,        ///< a constant position offset (ramped in over ramp_s)
  fix_quality,  ///< the reported quality forced (rtk-fixed, rtk-float, dgps, gps, estimated)
  degrade,      ///< fewer satellites used, DOP x k, error x k
  silence,      ///< the receiver writes nothing
  jam,          ///< C/N0 down by db over ramp_s: weak satellites drop, accuracy follows, fix lost below 4
  sky_mask,     ///< azimuth/elevation sectors blocked: those satellites gone, DOPs from the rest (sky_faults.hpp)
  spoof,        ///< position (and time) dragged away at speed_mps, velocity consistent (sky_faults.hpp)
  time,         ///< a time jump or a GPS week-number rollover (sky_faults.hpp)
  reset,        ///< the receiver reboots: silent, then a cold start with its RAM configuration lost
  garble,       ///< bytes corrupted: sentences and frames with a flipped bit (bad checksum) or cut short
  latency,      ///< the epoch's bytes written late (delay_ms, jitter_ms), its time fields unchanged
};

/// One key a fault takes: its name (units in it) and what it means, with unit and range.
struct ParameterInfo {
  std::string_view key;
  std::string_view help;
};

/// One kind: its name and its own parameters (beside the keys every fault takes).
struct KindInfo {
  FaultKind kind;
  std::string_view name;
  std::array<std::string_view, 9> parameters;  ///< empty names after the last
};

/// Every kind, in catalogue order.
[[nodiscard]] const std::array<KindInfo, 14>& catalogue();
/// Every kind, in catalogue order.
inline constexpr std::array<FaultKind, 14> kAllKinds{
    FaultKind::outage,  FaultKind::freeze,   FaultKind::jump,  FaultKind::wrong, FaultKind::fix_quality,
    FaultKind::degrade, FaultKind::silence,  FaultKind::jam,   FaultKind::sky_mask, FaultKind::spoof,
    FaultKind::time,    FaultKind::reset,    FaultKind::garble, FaultKind::latency};

/// "outage", "fix-quality", ... (the scenario's `kind`).
[[nodiscard]] std::string_view kind_name(FaultKind kind);
/// The kind named `name`, if any.
[[nodiscard]] std::optional<FaultKind> parse_kind(std::string_view name);
/// Every kind's name, comma separated (for messages and help).
[[nodiscard]] std::string kind_names();
/// The parameters `kind` takes beside the common keys, in alphabetical order.
[[nodiscard]] std::vector<std::string_view> parameters_of(FaultKind kind);
/// A parameter's row (a kind's own or a common key), or null.
[[nodiscard]] const ParameterInfo* parameter_info(std::string_view key);

/// Where a fault's keys come from: a [[fault]] table (or a --tee file), or a live request.
enum class FaultSource { scenario, live };
/// The keys every fault takes from `source`, as messages list them: "kind, at, at_utc, where,
/// duration or end, receiver"; live: "fault, duration, where, receiver" (a live fault starts at the
/// next epoch: no at, at_utc or end).
[[nodiscard]] std::string_view common_keys(FaultSource source);
/// The common keys a live request takes beside "fault" (gpsemu ctl's flags).
inline constexpr std::array<std::string_view, 3> kLiveCommonKeys{"duration", "where", "receiver"};

/// A key without its unit ("speed_mps" -> "speed", "time_drift_ms_per_s" -> "time_drift"); the key
/// itself when it names no unit ("dop_k", "mask").
[[nodiscard]] std::string_view key_without_unit(std::string_view key);

}  // namespace gpsemu::faults
