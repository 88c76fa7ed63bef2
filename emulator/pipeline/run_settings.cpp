#include "emulator/pipeline/run_settings.hpp"

#include <cmath>

#include <fmt/format.h>

#include "emulator/config/config.hpp"
#include "emulator/config/receiver_config.hpp"
#include "emulator/config/validate.hpp"
#include "emulator/pipeline/receiver_state.hpp"
#include "emulator/pipeline/serial_line_check.hpp"
#include "emulator/pipeline/ubx_effects.hpp"

namespace gpsemu {
namespace {

std::chrono::nanoseconds to_ns(double seconds) { return std::chrono::nanoseconds{std::llround(seconds * 1e9)}; }

// The outputs, a serial one without a baud at the factory state's (the model's default baud).
std::vector<transport::OutputSpec> output_specs(const ReceiverSettings& receiver) {
  std::vector<transport::OutputSpec> specs = receiver.outputs;
  if (!factory_state(receiver)) return specs;
  for (transport::OutputSpec& spec : specs) {
    if (spec.kind == transport::OutputKind::serial && spec.baud_bps == 0) {
      spec.baud_bps = static_cast<int>(ubx::model_info(receiver.ublox_model).default_baud);
    }
  }
  return specs;
}

// The u-blox port's start settings (--protocol ubx / nmea+ubx): --receiver's model, the period of
// --rate, the sentences of --sentences (ubx: none unless given), NAV-PVT every epoch, the baud of
// a serial output, and as sAcc a tenth of the horizontal noise sigma a second (the speed itself
// is the truth's).
std::optional<ubx::SessionSettings> ubx_settings(const ReceiverSettings& receiver, const ReceiverOptions& options,
                                                 const TimelineSettings& timeline) {
  const bool factory = factory_state(receiver);
  if (receiver.protocol == Protocol::nmea && !factory) return std::nullopt;
  ubx::SessionSettings s;
  s.start.model = receiver.ublox_model;
  s.start.measurement_period = std::chrono::milliseconds{std::llround(1000.0 / timeline.rate_hz)};
  s.start.sentences = receiver.protocol == Protocol::ubx && !receiver.sentences_given ? nmea::SentenceSet{}
                                                                                     : receiver.format.sentences;
  if (!factory) s.start.ubx_messages = {ubx::msg::nav_pvt};  // from the factory: NMEA alone until a driver asks
  for (const transport::OutputSpec& spec : receiver.outputs) {
    if (spec.kind == transport::OutputKind::serial) {
      const int fallback = factory ? 0 : nmea::kDefaultBaud;  // 0: the model's default baud
      s.start.baud = static_cast<std::uint32_t>(spec.baud_bps != 0 ? spec.baud_bps : fallback);
    }
  }
  if (receiver.receiver_state) s.stored = read_receiver_state(*receiver.receiver_state, receiver.ublox_model);
  s.format = receiver.format;
  s.speed_sigma_mps = 0.1 * std::hypot(options.noise_sigma_m.east_m, options.noise_sigma_m.north_m);
  s.seed = receiver.seed;
  return s;
}

// The widest epoch of a receiver's protocols: its NMEA sentences, or the u-blox port's at start.
// Sized on the model's worst case by system (each system its own GSV group and GSA).
std::size_t widest_epoch_bytes(const nmea::FormatOptions& format, const Geometry& sky,
                               const std::optional<ubx::SessionSettings>& ubx) {
  if (!ubx) return worst_case_epoch_bytes(format, sky.in_view_by_system, sky.satellites_used);
  return widest_ubx_epoch_bytes(format, ubx::start_settings(ubx->start), ubx->start.port, ubx->start.model, sky);
}

}  // namespace

void add_faults(ChannelSettings& channel, const std::vector<faults::Fault>& scenario, std::size_t i, std::size_t receivers) {
  faults::FaultPlan& plan = channel.faults;
  for (const faults::Fault& f : scenario) {
    if (f.receiver && static_cast<std::size_t>(*f.receiver) != i) continue;
    plan.faults.push_back(f);
    // A jam acts on each satellite's C/N0: the sky fills them even when no sentence lists them.
    if (f.kind == faults::FaultKind::jam) channel.receiver.satellite_details = true;
  }
  if (receivers > 1) plan.who = fmt::format("receiver {}: ", i);
}

LoopSettings loop_settings(const TimelineSettings& timeline) {
  LoopSettings loop;
  loop.rate_hz = timeline.rate_hz;
  loop.latency = to_ns(timeline.latency_s);
  loop.start_time = timeline.start_time;
  if (timeline.duration_s) loop.epochs = std::llround(*timeline.duration_s * timeline.rate_hz);
  loop.clock = timeline.clock;
  if (timeline.pps && !timeline.fast()) loop.pps.spec = timeline.pps;
  loop.pps.width = to_ns(timeline.pps_width_s);
  loop.pps.active_low = timeline.pps_active_low;
  return loop;
}

ReceiverSetup receiver_setup(const ReceiverSettings& receiver, const TimelineSettings& timeline) {
  ReceiverSetup r;
  const ReceiverOptions options = receiver_options(receiver);
  r.channel = {.origin = receiver.origin,
               .receiver = options,
               .noise = receiver.noise,
               .seed = receiver.seed,
               .format = receiver.format,
               .ubx = ubx_settings(receiver, options, timeline),
               .receiver_state = receiver.receiver_state,
               .faults = {},
               .rtk = receiver.rtk,
               .rtcm = receiver.rtcm,
               .moving_base = receiver.moving_base};
  r.outputs = {.outputs = output_specs(receiver),
               .tee = receiver.tee,
               .realtime = !timeline.fast(),
               .rate_hz = timeline.rate_hz,
               .widest_epoch_bytes = [format = receiver.format, sky = resolve_geometry(options), ubx = r.channel.ubx] {
                   return widest_epoch_bytes(format, sky, ubx);
                 }};
  r.sim_source = receiver.source.kind == sources::SourceKind::sim;
  r.source_text = receiver.source.text;
  r.make_source = [receiver, timeline](const LocalFrame& frame, UtcNs first_epoch) {
    return make_receiver_source(receiver, timeline, frame, first_epoch);
  };
  r.check_source = [receiver, timeline] { check_source_clock(receiver, timeline); };
  return r;
}

RunSettings run_settings(const Config& config) {
  RunSettings run;
  run.loop = loop_settings(config.timeline);
  run.control_path = config.process.control_path;
  run.control_idle_timeout = std::chrono::milliseconds(std::llround(config.process.control_idle_timeout_s * 1000.0));
  run.status_every = std::chrono::nanoseconds(std::llround(config.process.status_every_s * 1e9));
  run.watched = config.process.ui || config.process.control_path || config.process.status_every_s > 0.0;
  for (const ReceiverSettings& r : config.receivers) run.receivers.push_back(receiver_setup(r, config.timeline));
  for (std::size_t i = 0; i < run.receivers.size(); ++i)
    add_faults(run.receivers[i].channel, config.timeline.faults, i, run.receivers.size());
  return run;
}

ReplayPacing replay_pacing(const TimelineSettings& timeline, const ReplaySettings& replay) {
  ReplayPacing p;
  p.options = replay;
  p.fast = timeline.fast();
  if (timeline.duration_s) p.duration = to_ns(*timeline.duration_s);
  p.latency = to_ns(timeline.latency_s);
  p.start_time = timeline.start_time;
  return p;
}

}  // namespace gpsemu
