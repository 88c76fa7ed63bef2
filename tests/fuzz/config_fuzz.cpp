// libFuzzer target for the TOML config file (`--config FILE`, emulator/config/config.hpp): the bytes as
// the file's text through build_config_from_text() — TOML parsing, every option's value parser
// (the same ones the command line uses) and the derived settings. Checks:
//  - only ConfigError comes out, with a message; a message about the file names it;
//  - the result is deterministic, and a command-line value overrides the file's;
//  - an accepted config is in range: the rate makes an epoch grid, latency, decimals, horizon
//    within their limits; the clock, noise model and start time write back to what they were
//    read from; every output spec either is refused with std::invalid_argument or writes back
//    to a spec that parses to the same value.
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

void check_config(const Config& c) {
  GPSEMU_FUZZ_CHECK(c.rate_hz >= 0.1 && c.rate_hz <= 50.0);
  (void)EpochGrid(c.rate_hz);  // throws (and so fails) if the rate was accepted but makes no grid
  GPSEMU_FUZZ_CHECK(c.latency_s >= 0.0 && c.latency_s <= 0.5);
  GPSEMU_FUZZ_CHECK(c.pose_horizon_s >= 0.0 && c.pose_horizon_s <= c.pose_timeout_s);
  GPSEMU_FUZZ_CHECK(c.format.minute_decimals >= 1 && c.format.minute_decimals <= 8);
  GPSEMU_FUZZ_CHECK(c.format.time_decimals >= 0 && c.format.time_decimals <= 3);
  GPSEMU_FUZZ_CHECK(!c.format.sentences.empty());
  GPSEMU_FUZZ_CHECK(std::abs(c.origin.lat_deg) <= 90.0 && std::abs(c.origin.lon_deg) <= 180.0 &&
                    std::isfinite(c.origin.alt_m));
  GPSEMU_FUZZ_CHECK(std::isfinite(c.width_m) && c.width_m > 0.0);
  if (c.duration_s) GPSEMU_FUZZ_CHECK(std::isfinite(*c.duration_s) && *c.duration_s >= 0.0);
  const ClockSpec clock = parse_clock_spec(to_string(c.clock));
  GPSEMU_FUZZ_CHECK(clock.kind == c.clock.kind && std::abs(clock.scale / c.clock.scale - 1.0) < 1e-6);
  GPSEMU_FUZZ_CHECK(noise::parse_model(noise::to_string(c.noise.model)) == c.noise.model);
  if (c.start_time) GPSEMU_FUZZ_CHECK(parse_iso8601_utc(format_iso8601_utc(*c.start_time)) == *c.start_time);
  if (c.pps) (void)transport::parse_pps_spec(*c.pps);
  GPSEMU_FUZZ_CHECK(!c.outputs.empty());
  for (const std::string& output : c.outputs) {
    transport::OutputSpec spec;
    try {
      spec = transport::parse_output_spec(output);
    } catch (const std::invalid_argument& e) {
      GPSEMU_FUZZ_CHECK(*e.what() != '\0');
      continue;
    }
    GPSEMU_FUZZ_CHECK(transport::parse_output_spec(transport::to_string(spec)) == spec);
  }
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
  GPSEMU_FUZZ_CHECK(again.config->outputs == first.config->outputs && again.config->source == first.config->source &&
                    again.config->seed == first.config->seed && again.config->rate_hz == first.config->rate_hz);
  // The command line wins over the file (the seed has no derived settings, so this must build).
  const Outcome seeded = build(text, {{"seed", {"987654321"}}});
  GPSEMU_FUZZ_CHECK(seeded.config && seeded.config->seed == 987654321 &&
                    seeded.config->outputs == first.config->outputs);
  return 0;
}
