#include "emulator/pipeline/run_settings.hpp"

#include <cmath>

#include <fmt/format.h>

#include "emulator/config/config.hpp"
#include "emulator/config/receiver_config.hpp"
#include "emulator/config/validate.hpp"
#include "emulator/pipeline/serial_line_check.hpp"
#include "emulator/protocol/registry.hpp"
#include "transport/posix/fd.hpp"

namespace gpsemu {
namespace {

std::chrono::nanoseconds to_ns(double seconds) { return std::chrono::nanoseconds{std::llround(seconds * 1e9)}; }

// The outputs, a serial one without a baud at the factory state's (the model's default baud).
std::vector<transport::OutputSpec> output_specs(const ReceiverSettings& receiver) {
  std::vector<transport::OutputSpec> specs = receiver.outputs;
  const int factory_baud = protocol::factory_baud(receiver);
  if (factory_baud == 0) return specs;
  for (transport::OutputSpec& spec : specs) {
    if (spec.kind == transport::OutputKind::serial && spec.baud_bps == 0) spec.baud_bps = factory_baud;
  }
  return specs;
}

}  // namespace

void add_faults(ChannelSettings& channel, const std::vector<faults::Fault>& scenario, std::size_t i, std::size_t receivers) {
  faults::FaultPlan& plan = channel.faults;
  for (const faults::Fault& f : scenario) {
    if (f.receiver && static_cast<std::size_t>(*f.receiver) != i) continue;
    plan.faults.push_back(f);
    // A jam acts on each satellite's C/N0: the sky fills them even when no sentence lists them.
    if (f.is<faults::Jam>()) channel.receiver.satellite_details = true;
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
               .protocol = protocol::protocol_for(receiver, options, timeline, posix::replace_file),
               .faults = {},
               .rtk = receiver.rtk,
               .rtcm = receiver.rtcm,
               .moving_base = receiver.moving_base};
  r.outputs = {.outputs = output_specs(receiver),
               .tee = receiver.tee,
               .realtime = !timeline.fast(),
               .rate_hz = timeline.rate_hz,
               .widest_epoch_bytes = [spec = r.channel.protocol, sky = resolve_geometry(options)] {
                   return spec->widest_epoch_bytes(sky);
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
