#include "emulator/faults/catalogue.hpp"

#include <algorithm>

namespace gpsemu::faults {
namespace {

constexpr std::array<KindInfo, 14> kCatalogue{{
    {FaultKind::outage, "outage", {}},
    {FaultKind::freeze, "freeze", {}},
    {FaultKind::jump, "jump", {"east_m", "north_m", "up_m", "decay_s"}},
    {FaultKind::wrong, "wrong", {"east_m", "north_m", "up_m", "ramp_s", "ramp_out_s"}},
    {FaultKind::fix_quality, "fix-quality", {"quality"}},
    {FaultKind::degrade, "degrade", {"satellites", "dop_k", "noise_k", "ramp_s", "ramp_out_s"}},
    {FaultKind::silence, "silence", {}},
    {FaultKind::jam, "jam", {"db", "leave", "ramp_s", "ramp_out_s"}},
    {FaultKind::sky_mask, "sky-mask", {"mask"}},
    {FaultKind::spoof, "spoof",
     {"speed_mps", "bearing_deg", "east_m", "north_m", "up_m", "ramp_s", "ramp_out_s", "time_drift_ms_per_s", "detected"}},
    {FaultKind::time, "time", {"mode", "jump_s", "leap_utc"}},
    {FaultKind::reset, "reset", {"silent_s", "ttff_s"}},
    {FaultKind::garble, "garble", {"rate"}},
    {FaultKind::latency, "latency", {"delay_ms", "jitter_ms"}},
}};

constexpr std::array<ParameterInfo, 33> kParameters{{
    // Every fault.
    {"kind", "the fault (outage, freeze, jump, ...)"},
    {"at", "start, seconds after the first epoch (default 0)"},
    {"at_utc", "start at this UTC time, YYYY-MM-DDThh:mm:ssZ, in place of at"},
    {"duration", "length, seconds (> 0; absent: to the end, or until cleared)"},
    {"end", "end, seconds after the first epoch (in place of duration)"},
    {"where", "active while the truth is inside: circle:LAT,LON,RADIUS_M or polygon:LAT,LON;LAT,LON;..."},
    {"receiver", "a fleet index from 0, or all (default all)"},
    // Each kind's own.
    {"east_m", "offset east, metres"},
    {"north_m", "offset north, metres"},
    {"up_m", "offset up, metres"},
    {"decay_s", "jump: the step decays with this time constant, seconds (absent: it stays)"},
    {"ramp_s", "reaches full strength over this long, seconds (default 0)"},
    {"ramp_out_s", "after its end fades to nothing over this long, seconds (default 0)"},
    {"quality", "gps, dgps, rtk-float, rtk-fixed or estimated"},
    {"satellites", "at most this many satellites used"},
    {"dop_k", "DOP factor, 1..100 (default: from the satellites dropped)"},
    {"noise_k", "factor on the position error and sigmas, 0..1000 (default dop_k)"},
    {"db", "C/N0 drop at full strength, dB, 0..60"},
    {"leave", "jam instead of --db: at full strength as far as leaves at most this many satellites tracked, from each epoch's C/N0 (3: the fix is lost whatever the sky)"},
    {"mask", "urban-canyon, tree-line, tunnel-entry or sectors FROM-TO:ELEV[,...] (degrees)"},
    {"speed_mps", "drag speed, m/s, 0..1000"},
    {"bearing_deg", "drag direction, degrees true, 0..360"},
    {"time_drift_ms_per_s", "the reported time drifts this much a second, ms/s, -1000..1000"},
    {"detected", "the receiver reports the spoofing: true or false (default false)"},
    {"mode", "jump, rollover or leap-second"},
    {"jump_s", "time jump, seconds (whole milliseconds, +-)"},
    {"leap_utc", "the inserted second, YYYY-MM-DDT23:59:60Z"},
    {"silent_s", "the reboot writes nothing for this long, seconds, 0..3600 (default 2)"},
    {"ttff_s", "then no fix for this long, seconds, 0..3600 (default 26)"},
    {"rate", "fraction of sentences and frames hit, 0..1"},
    {"delay_ms", "the bytes leave this late, ms, 0..60000"},
    {"jitter_ms", "plus a uniform draw in [0, jitter_ms), ms, 0..60000"},
    {"fault", "the fault (a live request's kind)"},
}};

/// Unit suffixes of keys, longest first (so "_ms_per_s" is not read as "_s").
constexpr std::array<std::string_view, 6> kUnits{"_ms_per_s", "_mps", "_deg", "_ms", "_m", "_s"};

}  // namespace

const std::array<KindInfo, 14>& catalogue() { return kCatalogue; }

std::string_view kind_name(FaultKind kind) {
  for (const KindInfo& k : kCatalogue) {
    if (k.kind == kind) return k.name;
  }
  return "?";
}

std::optional<FaultKind> parse_kind(std::string_view name) {
  for (const KindInfo& k : kCatalogue) {
    if (k.name == name) return k.kind;
  }
  return std::nullopt;
}

std::string kind_names() {
  std::string out;
  for (const KindInfo& k : kCatalogue) out += (out.empty() ? "" : ", ") + std::string(k.name);
  return out;
}

std::vector<std::string_view> parameters_of(FaultKind kind) {
  std::vector<std::string_view> out;
  for (const KindInfo& k : kCatalogue) {
    if (k.kind != kind) continue;
    for (const std::string_view p : k.parameters) {
      if (!p.empty()) out.push_back(p);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

const ParameterInfo* parameter_info(std::string_view key) {
  for (const ParameterInfo& p : kParameters) {
    if (p.key == key) return &p;
  }
  return nullptr;
}

std::string_view common_keys(FaultSource source) {
  return source == FaultSource::live ? "fault, duration, where, receiver" : "kind, at, at_utc, where, duration or end, receiver";
}

std::string_view key_without_unit(std::string_view key) {
  for (const std::string_view unit : kUnits) {
    if (key.size() > unit.size() && key.substr(key.size() - unit.size()) == unit) return key.substr(0, key.size() - unit.size());
  }
  return key;
}

}  // namespace gpsemu::faults
