#include "emulator/faults/fault_timeline.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <variant>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "emulator/faults/sky_faults.hpp"
#include "emulator/model/accuracy.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/model/receiver_models.hpp"

namespace gpsemu::faults {
namespace {

nmea::SatelliteInView& sat(nmea::Fix& fix, int i) { return fix.satellites[static_cast<std::size_t>(i)]; }

int count_used(const nmea::Fix& fix) {
  int n = 0;
  for (int i = 0; i < fix.satellites_in_view; ++i) n += fix.satellites[static_cast<std::size_t>(i)].used;
  return n;
}

/// DOPs and the reported accuracy of a fix scaled by `dop_k` and `sigma_k`.
void scale_dops(nmea::Fix& fix, double dop_k, double sigma_k) {
  fix.hdop *= dop_k;
  fix.vdop *= dop_k;
  fix.pdop *= dop_k;
  fix.tdop *= dop_k;
  fix.gdop *= dop_k;
  fix.sigma_lat_m *= sigma_k;
  fix.sigma_lon_m *= sigma_k;
  fix.sigma_alt_m *= sigma_k;
  fix.range_rms_m *= sigma_k;
}

/// The used satellites beyond `keep` stop being used, weakest first; returns how many stay used.
int keep_strongest(nmea::Fix& fix, int keep) {
  int used = count_used(fix);
  while (used > keep) {
    int weakest = -1;
    for (int i = 0; i < fix.satellites_in_view; ++i) {
      if (!sat(fix, i).used) continue;
      if (weakest < 0 || sat(fix, i).snr_dbhz.value_or(0) <= sat(fix, weakest).snr_dbhz.value_or(0)) weakest = i;
    }
    sat(fix, weakest).used = false;
    --used;
  }
  return used;
}

}  // namespace

void offset_position(nmea::Fix& fix, const Enu& offset, const LocalFrame& frame) {
  const Enu p = frame.to_enu({fix.lat_deg, fix.lon_deg, fix.alt_msl_m}) + offset;
  const Geodetic g = frame.to_geodetic(p);
  fix.lat_deg = g.lat_deg;
  fix.lon_deg = g.lon_deg;
  fix.alt_msl_m = g.alt_m;
}

void scale_error(nmea::Fix& fix, const Enu& truth_m, double k, const LocalFrame& frame) {
  const Enu p = frame.to_enu({fix.lat_deg, fix.lon_deg, fix.alt_msl_m});
  offset_position(fix, (k - 1.0) * (p - truth_m), frame);
}

void drop_fix(nmea::Fix& fix) {
  nmea::Fix lost;
  lost.time_utc = fix.time_utc;
  lost.satellites_in_view = fix.satellites_in_view;
  lost.satellites = fix.satellites;
  for (int i = 0; i < lost.satellites_in_view; ++i) sat(lost, i).used = false;
  fix = lost;
}

namespace {

/// What a kind's effect acts on at one epoch.
struct EpochContext {
  const Fault& fault;    ///< the common part (at_s, ramp_out_s, ...)
  double since_s = 0.0;  ///< the epoch, seconds after the first
  double start_s = 0.0;  ///< the start of this visit (`at`, or entering the area)
  double strength = 0.0;  ///< 0..1: ramp in and out
  nmea::Fix& fix;
  const std::optional<Enu>& truth_m;
  const LocalFrame& frame;
  RfState& rf;  ///< the epoch's front end
  EpochEffect& effect;
  const std::optional<nmea::Fix>& frozen;  ///< the fix a freeze repeats
  std::optional<double> ended_s;  ///< fading out: when it ended (spoof fades by its offsets)
};

// Each kind's effect on an epoch (its parameters, the epoch's context).
void act(const Outage&, EpochContext& c) {
  nmea::Fix none;
  none.time_utc = c.fix.time_utc;
  c.fix = none;
}

void act(const Freeze&, EpochContext& c) {
  if (!c.frozen) return;
  const nmea::UtcTime now = c.fix.time_utc;
  c.fix = *c.frozen;
  c.fix.time_utc = now;
}

/// jump, wrong: `offset_m` at the ramp's strength, decaying with `decay_s`.
void move_by(const Enu& offset_m, std::optional<double> decay_s, EpochContext& c) {
  if (!c.fix.has_fix()) return;
  double k = c.strength;
  if (decay_s) k *= std::exp(-(c.since_s - c.start_s) / *decay_s);
  offset_position(c.fix, k * offset_m, c.frame);
}
void act(const Jump& p, EpochContext& c) { move_by(p.offset_m, p.decay_s, c); }
void act(const Wrong& p, EpochContext& c) { move_by(p.offset_m, std::nullopt, c); }

void act(const ForcedQuality& p, EpochContext& c) {
  if (!c.fix.has_fix()) return;
  const double k = noise_scale(p.quality) / noise_scale(c.fix.quality);
  c.fix.quality = p.quality;
  scale_dops(c.fix, 1.0, k);
  sky::apply_accuracy_floor(c.fix);  // the new quality's floor
  if (c.truth_m) scale_error(c.fix, *c.truth_m, k, c.frame);
}

void act(const Degrade& p, EpochContext& c) {
  nmea::Fix& fix = c.fix;
  if (!fix.has_fix()) return;
  if (p.satellites) {
    // Satellites out of the solution at once: the DOPs are the geometry of the rest from the first
    // epoch (a receiver does not ramp its DOP); the error ramps in by noise_k (default the HDOP's rise).
    const sky::Dops before = used_dops(fix);
    const double hdop_before = fix.hdop;
    (void)keep_strongest(fix, *p.satellites);
    if (!resolve_used_set(fix, before, 1.0, std::nullopt, c.frame)) return;
    const double geometric_k = hdop_before > 0.0 ? fix.hdop / hdop_before : 1.0;
    if (p.dop_k) scale_dops(fix, 1.0 + c.strength * (*p.dop_k - 1.0), 1.0);
    const double nk = 1.0 + c.strength * (p.noise_k.value_or(p.dop_k.value_or(geometric_k)) - 1.0);
    // The sigmas grew with the geometry already; the error grows by the whole factor.
    scale_dops(fix, 1.0, nk / geometric_k);
    if (c.truth_m) scale_error(fix, *c.truth_m, nk, c.frame);
    return;
  }
  const double dop_k = p.dop_k.value_or(1.0);
  const double noise_k = p.noise_k.value_or(dop_k);
  const double dk = 1.0 + c.strength * (dop_k - 1.0);
  const double nk = 1.0 + c.strength * (noise_k - 1.0);
  scale_dops(fix, dk, nk);
  if (c.truth_m) scale_error(fix, *c.truth_m, nk, c.frame);
}

void act(const Silence&, EpochContext& c) { c.effect.silent = true; }

/// The C/N0 drop (dB) that leaves at most `leave` of the fix's satellites tracked: just enough to
/// take the next strongest under the tracking threshold (C/N0 are whole dB-Hz), at most kMaxJamDb.
double drop_leaving(const nmea::Fix& fix, int leave) {
  std::array<int, nmea::max_satellites> cn0{};
  std::size_t n = 0;
  for (int i = 0; i < fix.satellites_in_view; ++i) {
    const auto& s = fix.satellites[static_cast<std::size_t>(i)];
    if (s.snr_dbhz && *s.snr_dbhz >= kTrackingThresholdDbHz) cn0[n++] = *s.snr_dbhz;
  }
  const auto k = static_cast<std::size_t>(leave);
  if (n <= k) return 0.0;
  std::nth_element(cn0.begin(), cn0.begin() + static_cast<std::ptrdiff_t>(k), cn0.begin() + static_cast<std::ptrdiff_t>(n),
                   std::greater<>());
  return std::min(kMaxJamDb, cn0[k] - kTrackingThresholdDbHz + 0.5);
}

void act(const Jam& p, EpochContext& c) {
  nmea::Fix& fix = c.fix;
  const double drop_db = c.strength * (p.leave ? drop_leaving(fix, *p.leave) : p.db);
  RfState& rf = c.rf;
  rf.jamming_indicator = static_cast<std::uint8_t>(std::clamp(9.0 + 8.0 * drop_db, 0.0, 255.0));
  rf.jamming_state = drop_db < 6.0 ? 1 : drop_db < 15.0 ? 2 : 3;
  rf.agc_count = static_cast<std::uint16_t>(std::lround(3140.0 * std::max(0.1, 1.0 - drop_db / 40.0)));
  rf.noise_per_ms = static_cast<std::uint16_t>(std::lround(89.0 + 4.0 * drop_db));
  const sky::Dops before = used_dops(fix);
  for (int i = 0; i < fix.satellites_in_view; ++i) {
    nmea::SatelliteInView& s = sat(fix, i);
    if (!s.snr_dbhz) continue;
    const double cn0 = *s.snr_dbhz - drop_db;
    if (cn0 < kTrackingThresholdDbHz) {
      s.snr_dbhz.reset();
      s.used = false;
    } else {
      s.snr_dbhz = static_cast<int>(std::lround(cn0));
    }
  }
  // The DOPs of what is left; the tracking error grows as 1/sqrt(C/N0): x 10^(dB/20).
  (void)resolve_used_set(fix, before, std::pow(10.0, drop_db / 20.0), c.truth_m, c.frame);
}

void act(const SkyMask& p, EpochContext& c) { mask_sky(c.fix, p.mask, c.truth_m, c.frame); }

void act(const Spoof& p, EpochContext& c) {
  if (c.ended_s) {  // fading: the offsets reached shrink to nothing, not a strength
    spoof(c.fix, c.fault, p, c.since_s, c.frame, c.ended_s);
    return;
  }
  c.rf.spoof_detection_state = spoof_detection_state(p.detected);
  spoof(c.fix, c.fault, p, c.since_s, c.frame);
}

void act(const TimeFault& p, EpochContext& c) { shift_time(c.fix, p); }

void act(const Reset& p, EpochContext& c) {
  c.effect.silent = c.effect.silent || c.since_s < c.fault.at_s + p.silent_s;
}

void act(const Garble& p, EpochContext& c) { c.effect.garble_rate = std::max(c.effect.garble_rate, p.rate); }

void act(const Latency& p, EpochContext& c) {
  c.effect.delay_ms += p.delay_ms;
  c.effect.jitter_ms += p.jitter_ms;
}

/// What a kind's start acts on beside the epoch (the timeline's state).
struct Moment {
  const std::optional<nmea::Fix>& last;   ///< the last epoch's fix as written
  std::optional<nmea::Fix>& frozen;       ///< the fix a freeze repeats
  EpochEffect& effect;
};

// A kind's first epoch (most do nothing then beyond their effect).
template <class Kind>
void on_start(const Kind&, Moment&) {}
void on_start(const Freeze&, Moment& m) { m.frozen = m.last; }
void on_start(const Reset& p, Moment& m) { m.effect.reboot_cold_start_s = p.silent_s + p.ttff_s; }

}  // namespace

FaultTimeline::FaultTimeline(FaultPlan plan, UtcNs first_epoch) : who_(std::move(plan.who)), first_epoch_(first_epoch) {
  for (Fault& f : plan.faults) {
    keeps_last_ = keeps_last_ || f.is<Freeze>();
    // at_utc: its time after the first epoch (before it: negative, active from the start if it lasts).
    if (f.at_utc) f.at_s = std::chrono::duration<double>(*f.at_utc - first_epoch).count();
    entries_.push_back({std::move(f)});
  }
}

namespace {

std::int64_t ns_of(double s) { return std::llround(s * 1e9); }

/// Faults whose effect fades out over ramp_out_s after they end (only the kinds that take the key
/// have one: jam, wrong, degrade, spoof).
bool fades(const Fault& f) { return f.ramp_out_s > 0.0; }

}  // namespace

void FaultTimeline::take_pending(UtcNs t, double since_s, const nmea::Fix& fix) {
  applied_.clear();
  // The clears first: a clear took the live faults of its kind accepted before it off pending_
  // (clear()), so those still pending came after it and must not end with it.
  for (auto& [kind, request] : pending_clears_) {
    for (Entry& e : entries_) {
      if (e.fault.kind() != kind || e.ended || e.cleared) continue;
      e.cleared = true;
      e.cleared_s = since_s;
      if (!e.active && !e.fading_from_s) e.ended = true;  // had not started: it never will
    }
    if (!request.empty()) applied_.push_back({t, since_s, std::move(request)});
  }
  pending_clears_.clear();
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    Fault& f = pending_[i];
    f.at_s = since_s;
    keeps_last_ = keeps_last_ || f.is<Freeze>();
    if (keeps_last_ && !last_) last_ = fix;  // a live freeze before any was kept: this epoch's
    entries_.push_back({std::move(f)});
    if (!pending_requests_[i].empty()) applied_.push_back({t, since_s, std::move(pending_requests_[i])});
  }
  pending_.clear();
  pending_requests_.clear();
  for (const AppliedEvent& a : applied_) {
    (void)log_limited(applied_log_, spdlog::level::info, "{}control: applied {} at epoch {} (+{:.3f} s)", who_,
                                 a.request, format_iso8601_utc(t), since_s);
  }
}

bool FaultTimeline::active_now(Entry& e, double since_s, const std::optional<Enu>& truth_m, const LocalFrame& frame) const {
  const Fault& f = e.fault;
  if (e.cleared) return false;
  if (!f.where) return f.active_at(since_s);
  if (f.disarm_s && ns_of(since_s) >= ns_of(*f.disarm_s)) {
    e.cleared = true;  // a replayed clear: over for good, as the live one was
    e.cleared_s = *f.disarm_s;
    return false;
  }
  const bool inside = truth_m && ns_of(since_s) >= ns_of(f.at_s) && f.where->contains(frame.to_geodetic(*truth_m));
  if (!inside) {
    e.entered_s.reset();
    return false;
  }
  if (!e.entered_s) e.entered_s = since_s;
  return !f.duration_s || ns_of(since_s) < ns_of(*e.entered_s + *f.duration_s);
}

EpochEffect FaultTimeline::apply(UtcNs t, ReceiverEpoch& epoch, const std::optional<Enu>& truth_m, const LocalFrame& frame) {
  nmea::Fix& fix = epoch.fix;
  EpochEffect effect;
  const double since_s = std::chrono::duration<double>(t - first_epoch_).count();
  if (!pending_.empty() || !pending_clears_.empty() || !applied_.empty()) take_pending(t, since_s, fix);
  last_epoch_.epochs++;
  last_epoch_.since_s = since_s;
  if (entries_.empty()) {
    last_epoch_.quality = fix.quality;
    last_epoch_.satellites_used = fix.satellites_used;
    return effect;
  }
  bool freeze_ahead = false;
  Moment moment{last_, frozen_, effect};
  for (Entry& e : entries_) {
    if (e.ended) continue;
    const bool active = active_now(e, since_s, truth_m, frame);
    if (active && !e.active) {
      spdlog::info("{}fault {} starts at epoch {} (+{:.3f} s)", who_, e.fault.describe(), format_iso8601_utc(t), since_s);
      std::visit([&moment](const auto& params) { on_start(params, moment); }, e.fault.params);
      e.fading_from_s.reset();
    } else if (!active && e.active) {
      spdlog::info("{}fault {} ends at epoch {} (+{:.3f} s) after {} epochs{}", who_, kind_name(e.fault.kind()),
                   format_iso8601_utc(t), since_s, e.epochs,
                   fades(e.fault) ? fmt::format(", fading out over {:.6g} s", e.fault.ramp_out_s) : std::string());
      if (fades(e.fault)) e.fading_from_s = since_s;
    }
    e.active = active;
    // Ramp in from the start of this visit (`at`, or entering the area); fade out after the end.
    const double start_s = e.entered_s.value_or(e.fault.at_s);
    double strength = 0.0;
    if (active) {
      strength = e.fault.ramp_s > 0.0 ? std::clamp((since_s - start_s) / e.fault.ramp_s, 0.0, 1.0) : 1.0;
      e.strength = strength;
    } else if (e.fading_from_s) {
      strength = e.strength * std::clamp(1.0 - (since_s - *e.fading_from_s) / e.fault.ramp_out_s, 0.0, 1.0);
      if (strength <= 0.0) e.fading_from_s.reset();
    }
    // The fade is over when its strength reaches nothing (a spoof's too: ramp_out_s after its end).
    if (active || e.fading_from_s) {
      ++e.epochs;
      const std::optional<double> ended_s = active ? std::nullopt : e.fading_from_s;
      EpochContext c{e.fault, since_s, start_s, strength, fix, truth_m, frame, epoch.rf, effect, frozen_, ended_s};
      std::visit([&c](const auto& params) { act(params, c); }, e.fault.params);
    } else {
      // Over for good: its time passed, or cleared (an area's fault can start again on the next visit).
      const bool past = e.fault.duration_s && !e.fault.where && ns_of(since_s) >= ns_of(e.fault.at_s + *e.fault.duration_s);
      e.ended = e.cleared || past;
    }
    freeze_ahead = freeze_ahead || (e.fault.is<Freeze>() && !e.ended);
  }
  keeps_last_ = freeze_ahead;
  last_epoch_.quality = fix.quality;
  last_epoch_.satellites_used = fix.satellites_used;
  last_epoch_.silent = effect.silent;
  if (keeps_last_) {
    last_ = fix;
  } else {
    last_.reset();
  }
  return effect;
}

int FaultTimeline::clear(FaultKind kind, std::string request) {
  int n = 0;
  for (const Entry& e : entries_) n += e.fault.kind() == kind && !e.ended && !e.cleared;
  int waiting = 0;
  for (std::size_t i = pending_.size(); i-- > 0;) {
    if (pending_[i].kind() != kind) continue;
    // Never applied: neither is it written to the --tee file.
    pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(i));
    pending_requests_.erase(pending_requests_.begin() + static_cast<std::ptrdiff_t>(i));
    ++waiting;
  }
  pending_clears_.emplace_back(kind, std::move(request));
  return n + waiting;
}

std::vector<std::string> FaultTimeline::summary_lines() const {
  std::vector<std::string> out;
  for (const Entry& e : entries_) {
    std::string what = e.fault.describe();
    if (e.cleared_s && !e.fault.where) {
      // It lasted from its start to the clear, unless its own end came first.
      const double start_s = e.fault.at_s;
      const bool ended_before = e.fault.duration_s && ns_of(start_s + *e.fault.duration_s) <= ns_of(*e.cleared_s);
      if (!ended_before) {
        Fault until_clear = e.fault;
        if (ns_of(*e.cleared_s) <= ns_of(start_s)) {
          what = until_clear.describe() + " (cleared before it started)";
        } else {
          until_clear.duration_s = *e.cleared_s - start_s;
          what = until_clear.describe() + " (cleared)";
        }
      }
    } else if (e.cleared_s) {
      what += fmt::format(" (cleared at {:.6g} s)", *e.cleared_s);
    }
    out.push_back(fmt::format("{}fault {}: {} epochs", who_, what, e.epochs));
  }
  return out;
}

void FaultTimeline::log_summary() const {
  for (const std::string& line : summary_lines()) spdlog::info("{}", line);
}

}  // namespace gpsemu::faults
