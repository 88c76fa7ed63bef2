// One type per fault kind, each with only its own parameters (docs/faults.md, "The catalogue"):
// a Fault (fault.hpp) is the part every kind shares (when, for which receiver, where, its ramp)
// and one of these. The alternatives of FaultParams are in catalogue order, so a kind's FaultKind
// is its index. Each kind's keys are parsed by fault.cpp's parse_key/finish overloads and its
// effect on an epoch is fault_timeline.cpp's act() overload (sky_faults.hpp for sky-mask, spoof
// and time; the channel for the byte-level ones through EpochEffect).
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "emulator/faults/catalogue.hpp"
#include "emulator/model/enu.hpp"
#include "emulator/model/sky.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::faults {

/// No satellites, no fix.
struct Outage {};
/// The last fix repeated with new times (PX4's "stuck").
struct Freeze {};
/// A position step, staying or decaying (multipath, a bad fix).
struct Jump {
  Enu offset_m{};                 ///< east_m, north_m, up_m
  std::optional<double> decay_s;  ///< the step decays with this time constant (seconds); empty: stays
};
/// A constant position offset (ramped in over the fault's ramp_s).
struct Wrong {
  Enu offset_m{};  ///< east_m, north_m, up_m
};
/// The reported quality forced.
struct ForcedQuality {
  nmea::FixQuality quality = nmea::FixQuality::gps;  ///< `quality`
};
/// Fewer satellites used, DOP x k, error x k.
struct Degrade {
  std::optional<int> satellites;  ///< at most this many satellites used
  std::optional<double> dop_k;    ///< DOP factor (default: from the satellites dropped)
  std::optional<double> noise_k;  ///< factor on the position error and sigmas (default: dop_k)
};
/// The receiver writes nothing.
struct Silence {};
/// C/N0 down by db: weak satellites drop, accuracy follows, fix lost below 4.
struct Jam {
  double db = 0.0;  ///< C/N0 reduction at full strength (dB)
  /// Instead of db: at full strength, the drop that leaves at most this many satellites tracked,
  /// from the C/N0 of each epoch (the same reaction whatever the sky of the moment; 3: no fix).
  std::optional<int> leave;
};
/// Azimuth/elevation sectors blocked (sky_faults.hpp).
struct SkyMask {
  std::vector<SkyMaskSector> mask;  ///< the sectors blocked (`mask`: a preset or FROM-TO:ELEV,...)
  std::string mask_name;            ///< `mask` as given (for logs)
};
/// Position (and time) dragged away, velocity consistent (sky_faults.hpp).
struct Spoof {
  double speed_mps = 0.0;            ///< the position is dragged away at this speed (m/s)
  double bearing_deg = 0.0;          ///< towards this direction (degrees true)
  Enu offset_m{};                    ///< plus this offset (ramped in over the fault's ramp_s)
  double time_drift_ms_per_s = 0.0;  ///< the reported time drifts this much a second (ms/s)
  bool detected = false;             ///< the receiver says so (NAV-STATUS spoofDetState 3, else 1)
};

/// What a `time` fault does to the reported time.
enum class TimeFaultMode {
  jump,      ///< the reported time steps by jump_s (and stays off while the fault lasts)
  rollover,  ///< GPS week-number rollover as buggy firmware does it: the date 1024 weeks early
  leap_second,  ///< a leap second announced from the fault's start and inserted at the end of leap_day
};
/// A time jump, a GPS week-number rollover or a leap second (sky_faults.hpp).
struct TimeFault {
  TimeFaultMode mode = TimeFaultMode::jump;  ///< `mode`
  double jump_s = 0.0;                       ///< the step of a jump (seconds, whole milliseconds)
  /// mode leap-second: the UTC day at whose end the second is inserted (`leap_utc`, the inserted
  /// second itself: "2026-12-31T23:59:60Z")
  std::chrono::sys_days leap_day{};
};
/// The receiver reboots: silent, then a cold start with its RAM configuration lost.
struct Reset {
  double silent_s = 2.0;  ///< the receiver boots this long, writing nothing (seconds)
  double ttff_s = 26.0;   ///< then a cold start, no fix for this long (seconds)
};
/// Bytes corrupted: sentences and frames with a flipped bit (bad checksum) or cut short (garble.hpp).
struct Garble {
  double rate = 0.0;  ///< fraction of sentences and frames hit (0..1)
};
/// The epoch's bytes written late, its time fields unchanged.
struct Latency {
  double delay_ms = 0.0;   ///< the bytes leave this much after the epoch's deadline (ms)
  double jitter_ms = 0.0;  ///< plus a uniform draw in [0, jitter_ms) each epoch (ms)
};

/// A fault's own parameters: one alternative per kind, in FaultKind's (catalogue) order.
using FaultParams = std::variant<Outage, Freeze, Jump, Wrong, ForcedQuality, Degrade, Silence, Jam, SkyMask, Spoof,
                                 TimeFault, Reset, Garble, Latency>;
static_assert(std::variant_size_v<FaultParams> == kAllKinds.size(), "one alternative per FaultKind, in its order");
template <FaultKind K, class Params>
inline constexpr bool kKindIs = std::is_same_v<std::variant_alternative_t<static_cast<std::size_t>(K), FaultParams>, Params>;
static_assert(kKindIs<FaultKind::outage, Outage> && kKindIs<FaultKind::freeze, Freeze> && kKindIs<FaultKind::jump, Jump> &&
                  kKindIs<FaultKind::wrong, Wrong> && kKindIs<FaultKind::fix_quality, ForcedQuality> &&
                  kKindIs<FaultKind::degrade, Degrade> && kKindIs<FaultKind::silence, Silence> &&
                  kKindIs<FaultKind::jam, Jam> && kKindIs<FaultKind::sky_mask, SkyMask> &&
                  kKindIs<FaultKind::spoof, Spoof> && kKindIs<FaultKind::time, TimeFault> &&
                  kKindIs<FaultKind::reset, Reset> && kKindIs<FaultKind::garble, Garble> &&
                  kKindIs<FaultKind::latency, Latency>,
              "FaultParams' alternatives in FaultKind's order");

/// The kind of `params`: its alternative's index.
[[nodiscard]] inline FaultKind kind_of(const FaultParams& params) { return static_cast<FaultKind>(params.index()); }
/// The parameters of `kind` at their defaults (its alternative, default constructed).
[[nodiscard]] FaultParams default_params(FaultKind kind);

}  // namespace gpsemu::faults
