#include "emulator/config/validate.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/model/sky/orbits.hpp"
#include "emulator/model/receiver_models.hpp"

#include "emulator/config/config_options.hpp"

namespace gpsemu {
namespace {

/// "rate, latency, start-time, duration, fast, clock": the options of one scope, in table order.
std::string names_of(OptionScope scope) {
  std::string names;
  for (const auto& o : option_table()) {
    if (o.scope == scope) names += names.empty() ? o.name : ", " + o.name;
  }
  return names;
}

}  // namespace

const char* why_not_per_receiver(std::string_view name) {
  if (name == "config") return "a [[receiver]] table holds option keys only";
  if (name == "profile") return "a profile sets the rate, which all receivers share";
  const OptionDef* option = find_option(name);
  if (!option) return nullptr;
  switch (option->scope) {
    case OptionScope::timeline: {
      static const std::string why =
          fmt::format("all receivers of a process share one epoch timeline ({})", names_of(OptionScope::timeline));
      return why.c_str();
    }
    case OptionScope::pps: return "a process drives at most one PPS line, for all its receivers";
    case OptionScope::process: return "it is a setting of the whole process";
    case OptionScope::replay: return "it applies to 'gpsemu replay' only";
    case OptionScope::fleet: return "the number of receivers is the number of [[receiver]] tables";
    case OptionScope::receiver: return nullptr;
  }
  return nullptr;
}

bool is_replay_only(std::string_view name) {
  const OptionDef* option = find_option(name);
  return option && option->scope == OptionScope::replay;
}

void check_fleet_size(ConfigDraft& draft, const std::string& file_name) {
  if (draft.receiver_tables.empty()) return;
  const int tables = static_cast<int>(draft.receiver_tables.size());
  if (tables > kMaxReceivers) {
    throw ConfigError(fmt::format("config file {}: {} [[receiver]] tables: at most {} receivers in one process",
                                  file_name, tables, kMaxReceivers));
  }
  if (draft.receivers_given && draft.receivers != tables) {
    throw ConfigError(fmt::format("receivers is {} but config file {} has {} [[receiver]] tables: the tables make "
                                  "the receivers, so give one table per receiver or leave receivers out",
                                  draft.receivers, file_name, tables));
  }
  draft.receivers = tables;
}

void resolve_timeline(ConfigDraft& draft) {
  TimelineSettings& t = draft.timeline;
  if (t.clock.kind == ClockKind::fast) draft.fast = true;
  if (draft.fast && t.clock.kind != ClockKind::realtime && t.clock.kind != ClockKind::fast) {
    throw ConfigError(fmt::format("clock: --fast and --clock {} are two different clocks: give one", to_string(t.clock)));
  }
  if (draft.fast) t.clock.kind = ClockKind::fast;
  if (t.pps && (t.clock.kind == ClockKind::scaled || t.clock.kind == ClockKind::lockstep)) {
    throw ConfigError(fmt::format("pps: a PPS pulse marks real seconds; it cannot be used with --clock {}",
                                  to_string(t.clock)));
  }
  if (t.pps && t.fast()) throw ConfigError("pps: a PPS pulse marks real seconds; it cannot be used with --fast");
}

bool factory_state(const ReceiverSettings& receiver) {
  return !receiver.protocol_given && receiver.receiver_model != ReceiverModel::generic;
}

bool has_ubx_port(const ReceiverSettings& receiver) {
  return receiver.protocol != Protocol::nmea || factory_state(receiver);
}

ReceiverSettings resolve_receiver(const ReceiverDraft& draft, const TimelineSettings& timeline) {
  ReceiverSettings r = draft.settings;
  if (r.pose_horizon_s > r.pose_timeout_s) {
    throw ConfigError(fmt::format("pose-horizon {} s is longer than pose-timeout {} s: a pose cannot be "
                                  "extrapolated past the time it goes stale", r.pose_horizon_s, r.pose_timeout_s));
  }
  // The cgrw one knob fills every axis not given explicitly.
  // The preset's ratios are per 1 Hz sample, so a different measurement rate needs every axis.
  if (draft.cgrw_rate_hz && !(draft.cgrw_east && draft.cgrw_north && draft.cgrw_up)) {
    throw ConfigError("cgrw-rate applies to parameters measured at that rate: give cgrw-east, cgrw-north "
                      "and cgrw-up too (gpsemu calibrate writes all four keys)");
  }
  const auto& own = draft.composite_cgrw;
  if ((own[0] || own[1] || own[2]) && !(own[0] && own[1] && own[2]))
    throw ConfigError("composite-cgrw-east, composite-cgrw-north and composite-cgrw-up go together "
                      "(gpsemu calibrate writes all three)");
  if (own[0]) r.noise.composite.smooth_cgrw = std::array<noise::CgrwAxis, 3>{*own[0], *own[1], *own[2]};
  r.noise.cgrw = noise::cgrw_preset(draft.width_m);
  r.noise.cgrw.window_s = draft.settings.noise.cgrw.window_s;
  if (draft.cgrw_rate_hz) r.noise.cgrw.rate_hz = *draft.cgrw_rate_hz;
  if (draft.cgrw_east) r.noise.cgrw.east = *draft.cgrw_east;
  if (draft.cgrw_north) r.noise.cgrw.north = *draft.cgrw_north;
  if (draft.cgrw_up) r.noise.cgrw.up = *draft.cgrw_up;
  // The velocity's error: its own flags, else the defaults, none with --noise none.
  noise::VelocityNoiseParams& velocity = r.model.velocity;
  const bool no_noise = r.noise.model == noise::Model::none;
  velocity.white_sigma_mps = draft.velocity_white_mps.value_or(no_noise ? 0.0 : velocity.white_sigma_mps);
  velocity.wander_sigma_mps = draft.velocity_wander_mps.value_or(no_noise ? 0.0 : velocity.wander_sigma_mps);
  // The sky of the receiver model (docs/sky.md); a multi-system model's NMEA talker is GN.
  r.model.tracking = facts_of(r.receiver_model).tracking;
  if (!r.talker_given && r.model.tracking.systems.count() > 1) r.format.talker = "GN";
  r.format.gsv_second_signal = r.model.tracking.dual_band;
  // An M9N's SPG firmware uses RTCM3 corrections for DGNSS only: no RTK float or fixed (docs/rtk.md).
  if ((facts_of(r.receiver_model).corrections == Corrections::dgnss)) r.rtk.best = nmea::FixQuality::dgps;
  // A u-blox port writes its model's NMEA messages only: a sentence it lacks would be dropped silently.
  for (const nmea::SentenceType type : nmea::all_sentence_types) {
    if (!has_ubx_port(r) || !r.format.sentences.contains(type) ||
        facts_of(r.receiver_model).nmea_written.contains(type)) {
      continue;
    }
    throw ConfigError(fmt::format("sentences: a u-blox {} does not write {} (not a u-blox NMEA message; a moving-base "
                                  "rover's heading is in NAV-RELPOSNED): leave {} out, or give --protocol nmea for "
                                  "an NMEA receiver that writes it", facts_of(r.receiver_model).name,
                                  nmea::sentence_name(type), nmea::sentence_name(type)));
  }
  // The orbits are read here, with the configuration: the embedded sky's take 50-90 ms to parse,
  // and read by the first receiver's set-up they came after the run's first epoch was chosen, so
  // that epoch was written after its deadline (at 10 Hz, 20-80 ms late; skipped under the sanitizers).
  if (r.ephemeris) {
    try {
      r.model.orbits = sky::Orbits::from_rinex_nav(*r.ephemeris);
    } catch (const std::exception& e) {
      throw ConfigError(e.what());
    }
  } else {
    r.model.orbits = sky::Orbits::embedded_default();
  }
  if (r.format.time_decimals < 3 && timeline.rate_hz > std::pow(10.0, r.format.time_decimals)) {
    throw ConfigError(fmt::format(
        "rate {} Hz needs more than {} time decimals: successive epochs would repeat a time "
        "(set time-decimals to {})", timeline.rate_hz, r.format.time_decimals, timeline.rate_hz > 100 ? 3 : 2));
  }
  return r;
}

void check_source_clock(const ReceiverSettings& receiver, const TimelineSettings& timeline) {
  const sources::SourceSpec& spec = receiver.source;
  const bool lockstep = timeline.clock.kind == ClockKind::lockstep;
  if (lockstep && !spec.is_socket()) {
    throw std::invalid_argument(fmt::format("--clock lockstep follows a simulator's time stamps: it needs a udp: or "
                                            "tcp: source, not --source {}", spec.text));
  }
  if (!spec.on_wall_clock() || lockstep) return;
  if (timeline.clock.kind != ClockKind::realtime) {
    throw std::invalid_argument(fmt::format("--source {}: a socket source runs on the wall clock (or, with --clock "
                                            "lockstep, on the simulator's); it cannot be used with --clock {}",
                                            spec.text, to_string(timeline.clock)));
  }
  // Poses are placed at their arrival time on the wall clock, so epochs must be on it too
  // (lockstep places them at --start-time or the first epoch + their t instead).
  if (timeline.fast() || timeline.start_time) {
    throw std::invalid_argument(fmt::format("--source {}: a socket source runs on the wall clock; it cannot be "
                                            "combined with --fast or --start-time", spec.text));
  }
}

void check_subcommand(const Config& config, const std::string& subcommand) {
  if (config.receivers.size() > 1) {
    throw ConfigError(fmt::format("--receivers and [[receiver]] tables apply to the emulator loop, not to 'gpsemu {}'",
                                  subcommand));
  }
}

void check_emulator_run(const Config& config) {
  for (const ReceiverSettings& r : config.receivers) check_source_clock(r, config.timeline);
}

void check_replay_settings(const TimelineSettings& timeline, const ReplaySettings& replay, bool log_has_epochs,
                           const std::string& log_name) {
  if (timeline.clock.kind == ClockKind::scaled || timeline.clock.kind == ClockKind::lockstep) {
    throw std::invalid_argument(fmt::format("replay paces by the log's own times: use --speed K (or --fast), not "
                                            "--clock {}", to_string(timeline.clock)));
  }
  if (!log_has_epochs) throw std::invalid_argument(fmt::format("NMEA log '{}' has no epochs", log_name));
  if (replay.loop && timeline.fast() && !timeline.duration_s) {
    throw std::invalid_argument("--loop with --fast would never end: give --duration S (seconds of log time)");
  }
}

}  // namespace gpsemu
