// Google Benchmark for the pieces of one epoch: noise step, ENU -> WGS84 conversion, sentence
// formatting, and a whole epoch (receiver model + formatting [+ file output]), for the --fast
// throughput figure (GGA+RMC, cgrw) and for the default sentence set.
// Run: build/tests/bench/gpsemu_bench
#include <benchmark/benchmark.h>

#include "emulator/model/sky.hpp"

#include <memory>
#include <string>

#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/epoch_text.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/geo_near.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/sources/sim.hpp"
#include "nmea/sentences.hpp"
#include "transport/file_output.hpp"

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

// The receiver's path: noisy positions within metres of one another (emulator/model/geo_near.hpp).
void enu_to_geodetic_near(benchmark::State& state) {
  const gpsemu::LocalFrame frame(kOrigin);
  gpsemu::NearGeodetic near;
  double e = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(near.to_geodetic(frame, {e, 12.5, 0.3}));
    e = e > 3.0 ? -3.0 : e + 1e-3;
  }
}
BENCHMARK(enu_to_geodetic_near);

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

gpsemu::nmea::FormatOptions gga_rmc_options() {
  gpsemu::nmea::FormatOptions options;
  options.sentences = {};
  options.sentences.insert(gpsemu::nmea::SentenceType::rmc);
  options.sentences.insert(gpsemu::nmea::SentenceType::gga);
  return options;
}

/// GGA and RMC of one epoch into the reused epoch buffer (what the --fast loop formats).
void format_epoch_gga_rmc(benchmark::State& state) {
  auto fix = sample_fix();
  const auto options = gga_rmc_options();
  std::string text;
  for (auto _ : state) {
    gpsemu::format_epoch(fix, options, text);
    benchmark::DoNotOptimize(text.data());
    fix.time_utc += milliseconds(100);
    fix.lat_deg += 1e-7;
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text.size()));
}
BENCHMARK(format_epoch_gga_rmc);

/// One whole epoch as the main loop does it, through the receiver channel (pipeline/channel.hpp):
/// truth from the simulator, receiver model with cgrw noise and geodetic conversion, the sentences
/// published into one buffer; with `to_file`, written to a buffered file output (/dev/null) as
/// --fast --output file: does. Receiver options as the pipeline makes them (noise sigma estimated,
/// satellite details only when GSA/GSV are written).
void whole_epoch(benchmark::State& state, const std::string& scenario, gpsemu::nmea::FormatOptions options,
                 bool to_file) {
  const gpsemu::UtcNs start{seconds(1714564800)};
  gpsemu::ChannelSettings settings;
  settings.origin = kOrigin;
  settings.noise.cgrw = gpsemu::noise::cgrw_preset(1.0);
  settings.receiver.noise_sigma_m = gpsemu::estimate_noise_sigma_m(settings.noise, 1);
  settings.receiver.satellite_details = options.sentences.contains(gpsemu::nmea::SentenceType::gsa) ||
                                        options.sentences.contains(gpsemu::nmea::SentenceType::gsv);
  settings.format = options;
  gpsemu::Channel channel(settings, start);
  channel.set_source(gpsemu::sources::make_sim_source(scenario, {}, channel.frame(), start));
  const auto file = to_file ? std::make_unique<gpsemu::transport::FileOutput>("/dev/null", false) : nullptr;
  gpsemu::UtcNs t = start;
  for (auto _ : state) {
    (void)channel.step(t);
    if (file) (void)file->write_epoch(channel.bytes());
    benchmark::DoNotOptimize(channel.bytes().data());
    t += milliseconds(100);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(whole_epoch, gga_rmc_stationary_to_file, "stationary", gga_rmc_options(), true);
BENCHMARK_CAPTURE(whole_epoch, gga_rmc_circle, "circle", gga_rmc_options(), false);
BENCHMARK_CAPTURE(whole_epoch, default_set_circle, "circle", gpsemu::nmea::FormatOptions{}, false);
// The issue #24 pair: the u-blox default set (GSA/GSV per system of an M8N's real sky) beside GGA+RMC.
BENCHMARK_CAPTURE(whole_epoch, default_set_stationary_to_file, "stationary", gpsemu::nmea::FormatOptions{}, true);

/// The sky alone at 10 Hz: one fill an epoch (an az/el snapshot of every tracked satellite each
/// new GPS second, the used set and DOPs, the interpolated entries written into the fix).
void sky_fill(benchmark::State& state) {
  gpsemu::SkyOptions options;
  options.tracking = gpsemu::facts_of(gpsemu::ReceiverModel::generic).tracking;  // an M8N
  gpsemu::Sky sky(options, {kOrigin.lat_deg, kOrigin.lon_deg, kOrigin.alt_m - 34.0});
  gpsemu::UtcNs t{seconds(1714564800)};
  gpsemu::nmea::Fix fix;
  for (auto _ : state) {
    benchmark::DoNotOptimize(sky.fill(t, {}, fix));
    t += milliseconds(100);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(sky_fill);

}  // namespace

BENCHMARK_MAIN();
