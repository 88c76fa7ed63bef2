#include "emulator/pipeline/run_settings.hpp"

#include <cmath>

#include "emulator/config/config.hpp"
#include "emulator/config/receiver_config.hpp"
#include "emulator/config/validate.hpp"
#include "emulator/pipeline/serial_line_check.hpp"

namespace gpsemu {
namespace {

std::chrono::nanoseconds to_ns(double seconds) { return std::chrono::nanoseconds{std::llround(seconds * 1e9)}; }

}  // namespace

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
  r.channel = {.origin = receiver.origin,
               .receiver = receiver_options(receiver),
               .noise = receiver.noise,
               .seed = receiver.seed,
               .format = receiver.format};
  r.outputs = {.outputs = receiver.outputs,
               .tee = receiver.tee,
               .realtime = !timeline.fast(),
               .rate_hz = timeline.rate_hz,
               .widest_epoch_bytes = [format = receiver.format] { return worst_case_epoch_bytes(format); }};
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
  for (const ReceiverSettings& r : config.receivers) run.receivers.push_back(receiver_setup(r, config.timeline));
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
