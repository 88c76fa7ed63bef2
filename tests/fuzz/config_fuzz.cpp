// libFuzzer target for the TOML config file (`--config FILE`, emulator/config/config.hpp): the bytes as
// the file's text through build_config_from_text() — TOML parsing, every option's value parser
// (the same ones the command line uses) and the derived settings. Checks:
//  - only ConfigError comes out, with a message; a message about the file names it;
//  - the result is deterministic, and a command-line value overrides the file's;
//  - an accepted config is in range: the rate makes an epoch grid, latency, decimals, horizon
//    within their limits; the clock, noise model and start time write back to what they were
//    read from; every output spec (parsed at load) writes back to a spec that parses to the
//    same value.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "emulator/pipeline/clock.hpp"
#include "emulator/config/config.hpp"
#include "emulator/model/time.hpp"
#include "fuzz_check.hpp"
#include "transport/output_spec.hpp"
#include "transport/pps.hpp"

namespace {

using namespace gpsemu;

constexpr const char* kName = "fuzz.toml";

/// The config, or the error message.
struct Outcome {
  std::optional<Config> config;
  std::string error;
};

Outcome build(std::string_view text, const RawOptions& command_line) {
  try {
    return {build_config_from_text(text, kName, command_line), {}};
  } catch (const ConfigError& e) {
    return {std::nullopt, e.what()};
  }
}

void check_receiver(const ReceiverSettings& c) {
  GPSEMU_FUZZ_CHECK(c.pose_horizon_s >= 0.0 && c.pose_horizon_s <= c.pose_timeout_s);
  GPSEMU_FUZZ_CHECK(c.format.minute_decimals >= 1 && c.format.minute_decimals <= 8);
  GPSEMU_FUZZ_CHECK(c.format.time_decimals >= 0 && c.format.time_decimals <= 3);
  GPSEMU_FUZZ_CHECK(!c.format.sentences.empty());
  GPSEMU_FUZZ_CHECK(std::abs(c.origin.lat_deg) <= 90.0 && std::abs(c.origin.lon_deg) <= 180.0 &&
                    std::isfinite(c.origin.alt_m));
  for (const noise::CgrwAxis& axis : {c.noise.cgrw.east, c.noise.cgrw.north, c.noise.cgrw.up}) {
    GPSEMU_FUZZ_CHECK(std::isfinite(axis.width_m) && axis.width_m > 0.0);  // from the one knob or given
  }
  GPSEMU_FUZZ_CHECK(noise::parse_model(noise::to_string(c.noise.model)) == c.noise.model);
  GPSEMU_FUZZ_CHECK(!c.outputs.empty());
  // Every output spec was parsed when the config loaded, and writes back to a spec that parses to
  // the same value.
  for (const transport::OutputSpec& spec : c.outputs) {
    GPSEMU_FUZZ_CHECK(transport::parse_output_spec(transport::to_string(spec)) == spec);
  }
}

void check_config(const Config& c) {
  const TimelineSettings& t = c.timeline;
  GPSEMU_FUZZ_CHECK(t.rate_hz >= 0.1 && t.rate_hz <= 50.0);
  (void)EpochGrid(t.rate_hz);  // throws (and so fails) if the rate was accepted but makes no grid
  GPSEMU_FUZZ_CHECK(t.latency_s >= 0.0 && t.latency_s <= 0.5);
  if (t.duration_s) GPSEMU_FUZZ_CHECK(std::isfinite(*t.duration_s) && *t.duration_s >= 0.0);
  const ClockSpec clock = parse_clock_spec(to_string(t.clock));
  GPSEMU_FUZZ_CHECK(clock.kind == t.clock.kind && std::abs(clock.scale / t.clock.scale - 1.0) < 1e-6);
  if (t.start_time) GPSEMU_FUZZ_CHECK(parse_iso8601_utc(format_iso8601_utc(*t.start_time)) == *t.start_time);
  if (t.pps) GPSEMU_FUZZ_CHECK(transport::parse_pps_spec(transport::to_string(*t.pps)) == *t.pps);
  GPSEMU_FUZZ_CHECK(!c.receivers.empty());
  for (const ReceiverSettings& r : c.receivers) check_receiver(r);
}

/// The receivers' outputs, sources and seeds, to compare two loads.
bool same_receivers(const Config& a, const Config& b) {
  if (a.receivers.size() != b.receivers.size()) return false;
  for (std::size_t i = 0; i < a.receivers.size(); ++i) {
    const ReceiverSettings &x = a.receivers[i], &y = b.receivers[i];
    if (x.outputs != y.outputs || x.source.text != y.source.text || x.seed != y.seed) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const Outcome first = build(text, {});
  const Outcome again = build(text, {});
  GPSEMU_FUZZ_CHECK(first.config.has_value() == again.config.has_value() && first.error == again.error);
  if (!first.config) {
    GPSEMU_FUZZ_CHECK(!first.error.empty());
    if (first.error.rfind("config file", 0) == 0) {
      GPSEMU_FUZZ_CHECK(first.error.rfind(std::string("config file ") + kName, 0) == 0);
    }
    return 0;
  }
  check_config(*first.config);
  GPSEMU_FUZZ_CHECK(same_receivers(*again.config, *first.config) &&
                    again.config->timeline.rate_hz == first.config->timeline.rate_hz);
  // The command line wins over the file (the seed has no derived settings, so this must build).
  const Outcome seeded = build(text, {{"seed", {"987654321"}}});
  GPSEMU_FUZZ_CHECK(seeded.config && seeded.config->receivers.size() == first.config->receivers.size());
  for (std::size_t i = 0; i < first.config->receivers.size(); ++i) {
    const ReceiverSettings &got = seeded.config->receivers[i], &before = first.config->receivers[i];
    // Receiver i gets seed + i, unless its [[receiver]] table sets its own (then unchanged).
    GPSEMU_FUZZ_CHECK(got.seed == 987654321 + i || got.seed == before.seed);
    GPSEMU_FUZZ_CHECK(got.outputs == before.outputs);
  }
  return 0;
}
