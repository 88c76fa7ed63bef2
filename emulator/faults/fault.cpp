#include "emulator/faults/fault.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <set>
#include <stdexcept>
#include <utility>
#include <variant>

#include <fmt/format.h>

namespace gpsemu::faults {
namespace {

std::string list(const std::vector<std::string_view>& names) {
  if (names.empty()) return "none";
  return fmt::format("{}", fmt::join(names, ", "));
}

double number(const std::string& key, const FaultValue& value, double min, double max) {
  const double* x = std::get_if<double>(&value);
  if (!x) {
    const std::string& s = std::get<std::string>(value);
    char* end = nullptr;
    const bool numeric = !s.empty() && (std::strtod(s.c_str(), &end), end == s.c_str() + s.size());
    throw std::invalid_argument(fmt::format("{}: expected a number, got the string \"{}\"{}", key, s,
                                            numeric ? fmt::format(" (write {} = {}, without quotes)", key, s) : ""));
  }
  if (!std::isfinite(*x) || *x < min || *x > max)
    throw std::invalid_argument(fmt::format("{}: {} is outside [{}, {}]", key, *x, min, max));
  return *x;
}

int whole(const std::string& key, const FaultValue& value, int min, int max) {
  const double x = number(key, value, min, max);
  if (x != std::floor(x)) throw std::invalid_argument(fmt::format("{}: expected a whole number, got {}", key, x));
  return static_cast<int>(x);
}

std::string text(const std::string& key, const FaultValue& value) {
  const std::string* s = std::get_if<std::string>(&value);
  if (!s) throw std::invalid_argument(fmt::format("{}: expected a string, got {}", key, std::get<double>(value)));
  return *s;
}

nmea::FixQuality parse_quality(const std::string& s) {
  if (s == "gps") return nmea::FixQuality::gps;
  if (s == "dgps") return nmea::FixQuality::dgps;
  if (s == "rtk-float") return nmea::FixQuality::rtk_float;
  if (s == "rtk-fixed") return nmea::FixQuality::rtk_fixed;
  if (s == "estimated") return nmea::FixQuality::estimated;
  throw std::invalid_argument(
      fmt::format("quality: expected gps, dgps, rtk-float, rtk-fixed or estimated, got '{}' (no fix: kind = \"outage\")", s));
}

std::string_view quality_name(nmea::FixQuality q) {
  switch (q) {
    case nmea::FixQuality::dgps: return "dgps";
    case nmea::FixQuality::rtk_float: return "rtk-float";
    case nmea::FixQuality::rtk_fixed: return "rtk-fixed";
    case nmea::FixQuality::estimated: return "estimated";
    default: return "gps";
  }
}

bool yes_no(const std::string& key, const FaultValue& value) {
  if (const auto* s = std::get_if<std::string>(&value)) {
    if (*s == "true") return true;
    if (*s == "false") return false;
    throw std::invalid_argument(fmt::format("{}: expected true or false, got '{}'", key, *s));
  }
  return whole(key, value, 0, 1) == 1;
}

/// The sectors of a sky-mask's `mask`: the presets of docs/faults.md, or FROM-TO:ELEV sectors.
std::vector<SkyMaskSector> parse_fault_mask(const std::string& text) {
  // Trees along the west side of the road: nothing below 30 degrees from south through west to north.
  if (text == "tree-line") return {{180.0, 360.0, 30.0}};
  // A tunnel portal ahead (north): only a 60-degree window above 10 degrees is left.
  if (text == "tunnel-entry") return {{30.0, 330.0, 90.01}, {330.0, 30.0, 10.0}};
  if (text == "open") throw std::invalid_argument("mask: 'open' blocks nothing (urban-canyon, tree-line, tunnel-entry or FROM-TO:ELEV,...)");
  try {
    return parse_sky_mask(text);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("mask: {} (presets: urban-canyon, tree-line, tunnel-entry)", e.what()));
  }
}

/// The day a leap second ends: `text` is the inserted second, "YYYY-MM-DDT23:59:60Z".
std::chrono::sys_days parse_leap_second(const std::string& text) {
  constexpr std::string_view kSecond60 = "T23:59:60Z";
  const auto bad = [&text] {
    return std::invalid_argument(fmt::format(
        "leap_utc: expected the inserted second as YYYY-MM-DDT23:59:60Z (a leap second ends a UTC day), got '{}'", text));
  };
  if (text.size() != 10 + kSecond60.size() || text.substr(10) != kSecond60) throw bad();
  try {
    return std::chrono::floor<std::chrono::days>(parse_iso8601_utc(text.substr(0, 10) + "T23:59:59Z", UtcSuffix::required));
  } catch (const std::invalid_argument&) {
    throw bad();
  }
}

std::string leap_second_text(std::chrono::sys_days day) {
  return format_iso8601_utc(UtcNs{day.time_since_epoch()}).substr(0, 10) + "T23:59:60Z";
}

constexpr double kMaxSeconds = 1e9;
constexpr double kMaxOffsetM = 1e7;

void add(std::string& s, std::string_view key, double v) { s += fmt::format(" {}={}", key, v); }

void add_offset(std::string& s, const Enu& offset_m) {
  add(s, "east_m", offset_m.east_m);
  add(s, "north_m", offset_m.north_m);
  add(s, "up_m", offset_m.up_m);
}

/// east_m, north_m, up_m into `offset_m` (jump, wrong, spoof); false for another key.
bool parse_offset(Enu& offset_m, const std::string& key, const FaultValue& value) {
  double* axis = key == "east_m" ? &offset_m.east_m : key == "north_m" ? &offset_m.north_m : key == "up_m" ? &offset_m.up_m : nullptr;
  if (!axis) return false;
  *axis = number(key, value, -kMaxOffsetM, kMaxOffsetM);
  return true;
}

// Each kind's own parameters after its name, for describe() and parameters().
void add_parameters(std::string&, const Outage&) {}
void add_parameters(std::string&, const Freeze&) {}
void add_parameters(std::string& s, const Jump& p) {
  add_offset(s, p.offset_m);
  if (p.decay_s) add(s, "decay_s", *p.decay_s);
}
void add_parameters(std::string& s, const Wrong& p) { add_offset(s, p.offset_m); }
void add_parameters(std::string& s, const ForcedQuality& p) { s += fmt::format(" quality={}", quality_name(p.quality)); }
void add_parameters(std::string& s, const Degrade& p) {
  if (p.satellites) add(s, "satellites", *p.satellites);
  if (p.dop_k) add(s, "dop_k", *p.dop_k);
  if (p.noise_k) add(s, "noise_k", *p.noise_k);
}
void add_parameters(std::string&, const Silence&) {}
void add_parameters(std::string& s, const Jam& p) {
  if (p.leave) {
    add(s, "leave", *p.leave);
  } else {
    add(s, "db", p.db);
  }
}
void add_parameters(std::string& s, const SkyMask& p) { s += fmt::format(" mask={}", p.mask_name); }
void add_parameters(std::string& s, const Spoof& p) {
  add(s, "speed_mps", p.speed_mps);
  add(s, "bearing_deg", p.bearing_deg);
  if (p.offset_m.east_m != 0.0 || p.offset_m.north_m != 0.0 || p.offset_m.up_m != 0.0) add_offset(s, p.offset_m);
  if (p.time_drift_ms_per_s != 0.0) add(s, "time_drift_ms_per_s", p.time_drift_ms_per_s);
  s += p.detected ? " detected" : " undetected";
}
void add_parameters(std::string& s, const TimeFault& p) {
  if (p.mode == TimeFaultMode::rollover) {
    s += " mode=rollover";
  } else if (p.mode == TimeFaultMode::leap_second) {
    s += fmt::format(" mode=leap-second leap_utc={}", leap_second_text(p.leap_day));
  } else {
    add(s, "jump_s", p.jump_s);
  }
}
void add_parameters(std::string& s, const Reset& p) {
  add(s, "silent_s", p.silent_s);
  add(s, "ttff_s", p.ttff_s);
}
void add_parameters(std::string& s, const Garble& p) { add(s, "rate", p.rate); }
void add_parameters(std::string& s, const Latency& p) {
  add(s, "delay_ms", p.delay_ms);
  if (p.jitter_ms > 0.0) add(s, "jitter_ms", p.jitter_ms);
}

// Each kind's own keys (make_fault checked that the catalogue lists `key` for the kind; ramp_s
// and ramp_out_s are the Fault's). A kind without keys of its own takes none.
[[noreturn]] void unparsed(const std::string& key) {
  throw std::logic_error(fmt::format("{}: in the catalogue but not parsed (fault.cpp's parse_key)", key));
}
template <class Kind>
void parse_key(Kind&, const std::string& key, const FaultValue&) {
  unparsed(key);
}
void parse_key(Jump& p, const std::string& key, const FaultValue& value) {
  if (parse_offset(p.offset_m, key, value)) return;
  if (key != "decay_s") unparsed(key);
  p.decay_s = number(key, value, 0.001, kMaxSeconds);
}
void parse_key(Wrong& p, const std::string& key, const FaultValue& value) {
  if (!parse_offset(p.offset_m, key, value)) unparsed(key);
}
void parse_key(ForcedQuality& p, const std::string& key, const FaultValue& value) { p.quality = parse_quality(text(key, value)); }
void parse_key(Degrade& p, const std::string& key, const FaultValue& value) {
  if (key == "satellites") {
    p.satellites = whole(key, value, 0, static_cast<int>(nmea::max_satellites));
  } else if (key == "dop_k") {
    p.dop_k = number(key, value, 1.0, 100.0);
  } else if (key == "noise_k") {
    p.noise_k = number(key, value, 0.0, 1000.0);
  } else {
    unparsed(key);
  }
}
void parse_key(Jam& p, const std::string& key, const FaultValue& value) {
  if (key == "leave") {
    p.leave = whole(key, value, 0, static_cast<int>(nmea::max_satellites));
  } else {
    p.db = number(key, value, 0.0, kMaxJamDb);
  }
}
void parse_key(SkyMask& p, const std::string& key, const FaultValue& value) {
  p.mask_name = text(key, value);
  p.mask = parse_fault_mask(p.mask_name);
}
void parse_key(Spoof& p, const std::string& key, const FaultValue& value) {
  if (parse_offset(p.offset_m, key, value)) return;
  if (key == "speed_mps") {
    p.speed_mps = number(key, value, 0.0, 1000.0);
  } else if (key == "bearing_deg") {
    p.bearing_deg = number(key, value, 0.0, 360.0);
  } else if (key == "time_drift_ms_per_s") {
    p.time_drift_ms_per_s = number(key, value, -1000.0, 1000.0);
  } else if (key == "detected") {
    p.detected = yes_no(key, value);
  } else {
    unparsed(key);
  }
}
void parse_key(TimeFault& p, const std::string& key, const FaultValue& value) {
  if (key == "mode") {
    const std::string mode = text(key, value);
    if (mode == "jump") {
      p.mode = TimeFaultMode::jump;
    } else if (mode == "rollover") {
      p.mode = TimeFaultMode::rollover;
    } else if (mode == "leap-second") {
      p.mode = TimeFaultMode::leap_second;
    } else {
      throw std::invalid_argument(fmt::format("mode: expected jump, rollover or leap-second, got '{}'", mode));
    }
  } else if (key == "leap_utc") {
    p.leap_day = parse_leap_second(text(key, value));
  } else if (key == "jump_s") {
    p.jump_s = number(key, value, -kMaxSeconds, kMaxSeconds);
    if (p.jump_s * 1000.0 != std::round(p.jump_s * 1000.0))
      throw std::invalid_argument(fmt::format("jump_s: {} is not a whole number of milliseconds", p.jump_s));
  } else {
    unparsed(key);
  }
}
void parse_key(Reset& p, const std::string& key, const FaultValue& value) {
  if (key == "silent_s") {
    p.silent_s = number(key, value, 0.0, 3600.0);
  } else if (key == "ttff_s") {
    p.ttff_s = number(key, value, 0.0, 3600.0);
  } else {
    unparsed(key);
  }
}
void parse_key(Garble& p, const std::string& key, const FaultValue& value) { p.rate = number(key, value, 0.0, 1.0); }
void parse_key(Latency& p, const std::string& key, const FaultValue& value) {
  if (key == "delay_ms") {
    p.delay_ms = number(key, value, 0.0, 60000.0);
  } else if (key == "jitter_ms") {
    p.jitter_ms = number(key, value, 0.0, 60000.0);
  } else {
    unparsed(key);
  }
}

using Seen = std::set<std::string>;

// A kind's checks once its keys are read: those before the `end` key is turned into a duration
// (check_before_end), then the rest (finish, which may set the fault's duration).
template <class Kind>
void check_before_end(const Kind&, const Seen&) {}
void check_before_end(const Garble&, const Seen& seen) {
  if (!seen.count("rate")) throw std::invalid_argument("rate: missing (garble hits this fraction of sentences and frames, 0..1)");
}
void check_before_end(const Latency&, const Seen& seen) {
  if (!seen.count("delay_ms") && !seen.count("jitter_ms"))
    throw std::invalid_argument("delay_ms: missing (latency writes each epoch delay_ms late, plus up to jitter_ms)");
}

template <class Kind>
void finish(const Kind&, Fault&, const Seen&) {}
void finish(const ForcedQuality&, Fault&, const Seen& seen) {
  if (!seen.count("quality"))
    throw std::invalid_argument("quality: missing (fix-quality forces gps, dgps, rtk-float, rtk-fixed or estimated)");
}
void finish(const Jam&, Fault&, const Seen& seen) {
  if (seen.count("db") && seen.count("leave")) throw std::invalid_argument("jam: db or leave, not both");
  if (!seen.count("db") && !seen.count("leave"))
    throw std::invalid_argument("db: missing (jam lowers C/N0 by db dB; or leave = N: as far as leaves at most N "
                                "satellites tracked, whatever the sky)");
}
void finish(const SkyMask&, Fault&, const Seen& seen) {
  if (!seen.count("mask"))
    throw std::invalid_argument("mask: missing (urban-canyon, tree-line, tunnel-entry or FROM-TO:ELEV,... in degrees)");
}
void finish(const Spoof& p, Fault&, const Seen&) {
  if (p.speed_mps == 0.0 && p.offset_m.east_m == 0.0 && p.offset_m.north_m == 0.0 && p.offset_m.up_m == 0.0 &&
      p.time_drift_ms_per_s == 0.0)
    throw std::invalid_argument("spoof: give speed_mps (with bearing_deg), an offset (east_m, north_m, up_m) or time_drift_ms_per_s");
}
void finish(const TimeFault& p, Fault&, const Seen& seen) {
  if (!seen.count("mode")) throw std::invalid_argument("mode: missing (jump, rollover or leap-second)");
  if ((p.mode == TimeFaultMode::leap_second) != (seen.count("leap_utc") == 1))
    throw std::invalid_argument(p.mode == TimeFaultMode::leap_second
                                    ? "leap_utc: missing (the inserted second, e.g. \"2026-12-31T23:59:60Z\")"
                                    : "leap_utc: a parameter of mode = \"leap-second\" only");
  if (p.mode == TimeFaultMode::leap_second && seen.count("jump_s"))
    throw std::invalid_argument("jump_s: not a parameter of a leap second (it inserts one second at leap_utc)");
  if (p.mode == TimeFaultMode::jump && !seen.count("jump_s"))
    throw std::invalid_argument("jump_s: missing (a time jump steps the reported time by jump_s seconds)");
  if (p.mode == TimeFaultMode::rollover && seen.count("jump_s"))
    throw std::invalid_argument("jump_s: not a parameter of a rollover (it takes the date back 1024 weeks)");
}
void finish(const Reset& p, Fault& f, const Seen& seen) {
  if (seen.count("duration") || seen.count("end"))
    throw std::invalid_argument("reset: an event, it takes no duration or end (it lasts silent_s + ttff_s)");
  f.duration_s = p.silent_s + p.ttff_s;
  if (!(*f.duration_s > 0.0)) throw std::invalid_argument("reset: silent_s + ttff_s must be > 0 seconds");
}
void finish(const Degrade& p, Fault&, const Seen&) {
  if (!p.satellites && !p.dop_k && !p.noise_k) throw std::invalid_argument("degrade: give at least one of satellites, dop_k, noise_k");
}

template <std::size_t... I>
FaultParams default_params_at(std::size_t i, std::index_sequence<I...>) {
  static const std::array<FaultParams, sizeof...(I)> defaults{FaultParams(std::in_place_index<I>)...};
  return defaults.at(i);
}

}  // namespace

FaultParams default_params(FaultKind kind) {
  return default_params_at(static_cast<std::size_t>(kind), std::make_index_sequence<std::variant_size_v<FaultParams>>{});
}

std::string FaultOrigin::prefix(std::string_view key) const {
  if (file.empty()) return {};
  int line = table_line;
  for (const auto& [k, l] : key_lines) {
    if (k == key) line = l;
  }
  return fmt::format("{}:{}: [[fault]]: ", file, line);
}

double Fault::strength_at(double since_s) const {
  if (ramp_s <= 0.0) return 1.0;
  return std::clamp((since_s - at_s) / ramp_s, 0.0, 1.0);
}

std::string Fault::describe() const {
  std::string s = parameters();
  if (where) s += fmt::format(" where {}", where->text());
  if (at_utc) {
    s += fmt::format(" at_utc {}", format_iso8601_utc(*at_utc));
  } else if (!where || at_s > 0.0) {
    s += fmt::format(" at {:.6g} s", at_s);
  }
  s += duration_s ? fmt::format(" for {:.6g} s", *duration_s) : std::string(where ? "" : " to the end");
  if (receiver) s += fmt::format(", receiver {}", *receiver);
  return s;
}

std::string Fault::parameters() const {
  std::string s{kind_name(kind())};
  std::visit([&s](const auto& p) { add_parameters(s, p); }, params);
  if (ramp_s > 0.0) add(s, "ramp_s", ramp_s);
  if (ramp_out_s > 0.0) add(s, "ramp_out_s", ramp_out_s);
  return s;
}

Fault make_fault(const FaultKeys& keys, FaultSource source) {
  Fault f;
  const FaultValue* kind_value = nullptr;
  for (const auto& [key, value] : keys) {
    if (key == "kind") kind_value = &value;
  }
  const std::string kind_key = source == FaultSource::live ? "fault" : "kind";
  if (!kind_value) throw std::invalid_argument(fmt::format("{}: missing (one of {})", kind_key, kind_names()));
  const std::string kind = text(kind_key, *kind_value);
  const std::optional<FaultKind> found = parse_kind(kind);
  if (!found) throw std::invalid_argument(fmt::format("{}: unknown fault '{}' (one of {})", kind_key, kind, kind_names()));
  f.params = default_params(*found);

  const std::vector<std::string_view> own = parameters_of(*found);
  std::set<std::string> seen;
  std::optional<double> end_s;
  for (const auto& [key, value] : keys) {
    if (!seen.insert(key).second) throw std::invalid_argument(fmt::format("{}: given twice", key));
    if (key == "kind") continue;
    if (key == "at") {
      f.at_s = number(key, value, 0.0, kMaxSeconds);
    } else if (key == "duration") {
      f.duration_s = number(key, value, 0.0, kMaxSeconds);
      if (!(*f.duration_s > 0.0)) throw std::invalid_argument("duration: must be > 0 seconds (absent: to the end)");
    } else if (key == "end") {
      end_s = number(key, value, 0.0, kMaxSeconds);
    } else if (key == "at_utc") {
      try {
        f.at_utc = parse_iso8601_utc(text(key, value), UtcSuffix::required);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(fmt::format("at_utc: {}", e.what()));
      }
    } else if (key == "where") {
      f.where = parse_area(text(key, value));
    } else if (key == "receiver") {
      if (const auto* s = std::get_if<std::string>(&value)) {
        if (*s != "all") throw std::invalid_argument(fmt::format("receiver: expected an index from 0 or \"all\", got '{}'", *s));
      } else {
        f.receiver = whole(key, value, 0, 1 << 20);
      }
    } else if (std::find(own.begin(), own.end(), key) == own.end()) {
      throw std::invalid_argument(fmt::format("{}: not a parameter of {} (its parameters: {}; every {}fault: {})", key, kind,
                                              list(own), source == FaultSource::live ? "live " : "", common_keys(source)));
    } else if (key == "ramp_s") {  // the kinds that ramp in (catalogue.cpp)
      f.ramp_s = number(key, value, 0.0, kMaxSeconds);
    } else if (key == "ramp_out_s") {  // ... and fade out
      f.ramp_out_s = number(key, value, 0.0, kMaxSeconds);
    } else {
      // Named references: clang 14 captures no structured binding in a lambda (C++20's P1091 came later).
      const auto& k = key;
      const auto& v = value;
      std::visit([&k, &v](auto& p) { parse_key(p, k, v); }, f.params);
    }
  }
  if (f.at_utc && (seen.count("at") || seen.count("end")))
    throw std::invalid_argument("at_utc: give at (and end) or at_utc, not both (with at_utc: duration)");
  // The keys a kind requires that the end does not bear on are checked before it (the order of the messages).
  std::visit([&seen](const auto& p) { check_before_end(p, seen); }, f.params);
  if (end_s) {
    if (f.duration_s) throw std::invalid_argument("end: give duration or end, not both");
    if (!(*end_s > f.at_s)) throw std::invalid_argument(fmt::format("end: {} s is not after at ({} s)", *end_s, f.at_s));
    f.duration_s = *end_s - f.at_s;
  }
  std::visit([&f, &seen](const auto& p) { finish(p, f, seen); }, f.params);
  return f;
}

}  // namespace gpsemu::faults
