// Google Benchmark for the pieces of one epoch: noise step, ENU -> WGS84 conversion, sentence
// formatting, and a whole epoch (receiver model + formatting). Run: build/tests/bench/gpsemu_bench
#include <benchmark/benchmark.h>

#include <string>

#include "emulator/epoch_text.hpp"
#include "emulator/geo.hpp"
#include "emulator/noise/noise_model.hpp"
#include "emulator/receiver.hpp"
#include "emulator/sources/sim.hpp"
#include "nmea/sentences.hpp"

namespace {

using namespace std::chrono;
const gpsemu::Geodetic kOrigin{43.0725, -89.4125, 260.0};

void noise_model(benchmark::State& state, gpsemu::noise::Model model) {
  gpsemu::noise::NoiseConfig config;
  config.model = model;
  config.cgrw = gpsemu::noise::cgrw_preset(1.0);
  auto noise = gpsemu::noise::make_noise_model(config, 1);
  nanoseconds t{0};
  for (auto _ : state) {
    benchmark::DoNotOptimize(noise->offset_at(t));
    t += milliseconds(100);  // 10 Hz epochs
  }
}
BENCHMARK_CAPTURE(noise_model, cgrw_10hz, gpsemu::noise::Model::cgrw);
BENCHMARK_CAPTURE(noise_model, gaussian, gpsemu::noise::Model::gaussian);

void enu_to_geodetic(benchmark::State& state) {
  const gpsemu::LocalFrame frame(kOrigin);
  double e = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(frame.to_geodetic({e, 12.5, 0.3}));
    e += 1e-3;
  }
}
BENCHMARK(enu_to_geodetic);

gpsemu::nmea::Fix sample_fix() {
  gpsemu::nmea::Fix fix;
  fix.time_utc = gpsemu::nmea::UtcTime{milliseconds(1714564800100)};
  fix.quality = gpsemu::nmea::FixQuality::gps;
  fix.dimension = gpsemu::nmea::FixDimension::three_d;
  fix.lat_deg = 43.07251234;
  fix.lon_deg = -89.41253456;
  fix.alt_msl_m = 260.4;
  fix.speed_mps = 2.0;
  fix.course_deg_true = 90.0;
  fix.satellites_used = 12;
  fix.hdop = 0.8;
  return fix;
}

void format_gga(benchmark::State& state) {
  const auto fix = sample_fix();
  const gpsemu::nmea::FormatOptions options;
  for (auto _ : state) benchmark::DoNotOptimize(gpsemu::nmea::format_gga(fix, options));
}
BENCHMARK(format_gga);

void format_rmc(benchmark::State& state) {
  const auto fix = sample_fix();
  const gpsemu::nmea::FormatOptions options;
  for (auto _ : state) benchmark::DoNotOptimize(gpsemu::nmea::format_rmc(fix, options));
}
BENCHMARK(format_rmc);

/// One whole epoch as the main loop does it: truth from the simulator, receiver model with cgrw
/// noise and geodetic conversion, the configured sentences formatted into one buffer.
void whole_epoch(benchmark::State& state) {
  const gpsemu::LocalFrame frame(kOrigin);
  const gpsemu::UtcNs start{seconds(1714564800)};
  auto source = gpsemu::sources::make_sim_source("circle", {}, frame, start);
  gpsemu::noise::NoiseConfig config;
  config.cgrw = gpsemu::noise::cgrw_preset(1.0);
  gpsemu::Receiver receiver(frame, {}, gpsemu::noise::make_noise_model(config, 1), start);
  gpsemu::nmea::FormatOptions options;
  std::string text;
  gpsemu::UtcNs t = start;
  for (auto _ : state) {
    const auto fix = receiver.fix_at(t, source->truth_at(t));
    gpsemu::format_epoch(fix, options, text);
    benchmark::DoNotOptimize(text.data());
    t += milliseconds(100);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(whole_epoch);

}  // namespace

BENCHMARK_MAIN();
