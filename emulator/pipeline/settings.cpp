#include "emulator/pipeline/settings.hpp"

#include <cmath>

#include "emulator/config/fleet_config.hpp"
#include "emulator/config/receiver_config.hpp"
#include "emulator/pipeline/serial_line_check.hpp"
#include "emulator/sources/make_source.hpp"

namespace gpsemu {
namespace {

std::chrono::nanoseconds to_ns(double seconds) { return std::chrono::nanoseconds{std::llround(seconds * 1e9)}; }

}  // namespace

ReceiverSetup receiver_setup(const Config& config) {
  ReceiverSetup r;
  r.channel = {.origin = config.origin,
               .receiver = receiver_options(config),
               .noise = config.noise,
               .seed = config.seed,
               .format = config.format};
  r.outputs = {.outputs = config.outputs,
               .tee = config.tee,
               .realtime = !config.fast,
               .rate_hz = config.rate_hz,
               .widest_epoch_bytes = [format = config.format] { return worst_case_epoch_bytes(format); }};
  r.source_spec = config.source;
  r.make_source = [config](const LocalFrame& frame, UtcNs first_epoch) {
    return sources::make_source(config, frame, first_epoch);
  };
  return r;
}

LoopSettings loop_settings(const Config& config) {
  LoopSettings loop;
  loop.rate_hz = config.rate_hz;
  loop.latency = to_ns(config.latency_s);
  loop.start_time = config.start_time;
  if (config.duration_s) loop.epochs = std::llround(*config.duration_s * config.rate_hz);
  loop.clock = config.clock;
  if (config.fast) loop.clock.kind = ClockKind::fast;
  loop.pps = {.spec = config.pps && !config.fast ? *config.pps : std::string(),
              .width = to_ns(config.pps_width_s),
              .active_low = config.pps_active_low};
  return loop;
}

RunSettings run_settings(const Config& config) {
  RunSettings run;
  run.loop = loop_settings(config);
  for (const Config& rc : receiver_configs(config)) run.receivers.push_back(receiver_setup(rc));
  return run;
}

ReplaySettings replay_settings(const Config& config) {
  ReplaySettings r;
  r.options = config.replay;
  r.fast = config.fast || config.clock.kind == ClockKind::fast;
  r.clock = config.clock;
  if (config.duration_s) r.duration = to_ns(*config.duration_s);
  r.latency = to_ns(config.latency_s);
  r.start_time = config.start_time;
  r.outputs.outputs = config.outputs;
  r.outputs.tee = config.tee;
  r.outputs.realtime = !r.fast;
  return r;
}

}  // namespace gpsemu
