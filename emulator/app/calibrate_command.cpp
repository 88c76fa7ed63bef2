// `gpsemu calibrate LOG`, and the arguments it shares with `gpsemu compare`.
#include <cstdio>
#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "emulator/app/calibration_commands.hpp"
#include "emulator/calibration/report.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/config/config.hpp"

namespace gpsemu {
namespace {

constexpr const char* kHelp =
    "fit every noise model to a stationary receiver's NMEA log and write a config file the emulator "
    "loads with --config (noise = the best-scoring model)";

}  // namespace

CLI::App* add_calibration_subcommand(CLI::App& app, const std::string& name, const std::string& description,
                                     const std::shared_ptr<CalibrationArgs>& args) {
  CLI::App* sub = app.add_subcommand(name, description);
  sub->add_option("log", args->log, "NMEA log of a stationary receiver (binary and junk are skipped)")
      ->required()
      ->check(CLI::ExistingFile)
      ->option_text("LOG");
  sub->add_option("--runs", args->runs, "simulated runs per model, seeds --seed, --seed+1, ... (default 32: the mean of 8 runs of a few minutes of log varies by 20% between seed sets); the composite's refits take as many, 8 at least; below 8 a quick calibration: the composite's refits search less (docs/noise-and-calibration.md)")
      ->check(CLI::Range(1, 1000))
      ->option_text("N");
  sub->add_flag("--detrend", args->detrend,
                "the log moves: remove a smooth trajectory (local quadratic over 10 s) first and calibrate the "
                "rest (default: a log that moves is refused, exit 2)");
  return sub;
}

calibration::CalibrateOptions calibration_options(const CalibrationArgs& args, std::uint64_t seed) {
  calibration::CalibrateOptions o;
  o.seed = seed;
  o.runs = args.runs;
  o.detrend = args.detrend;
  std::ifstream meminfo("/proc/meminfo");
  for (std::string line; std::getline(meminfo, line);) {
    unsigned long long kib = 0;  // "MemAvailable:   12345678 kB"
    if (std::sscanf(line.c_str(), "MemAvailable: %llu kB", &kib) != 1) continue;
    o.max_epochs = calibration::max_epochs_for_memory(kib * 1024);
    o.max_epochs_reason = fmt::format("{} bytes an epoch in at most half of the {:.0f} MB of memory available",
                                      calibration::kCalibrationBytesPerEpoch, static_cast<double>(kib) / 1024.0);
    break;
  }
  return o;
}

calibration::Calibration run_calibration(const CalibrationArgs& args, std::uint64_t seed) {
  return calibration::calibrate(calibration::read_receiver_log_file(args.log), calibration_options(args, seed));
}

calibration::ReceiverState learned_receiver_state(const std::string& log, const calibration::Calibration& c) {
  std::ifstream in(log, std::ios::binary);
  // The emulator's accuracy starts from the model's long-run sigma (estimate_noise_sigma_m): the
  // ratio makes it what the receiver claimed.
  const Enu model = estimate_noise_sigma_m(c.models[c.best].config, 1);
  return calibration::with_sigmas(calibration::learn_receiver_state(in), std::hypot(c.real[0].sd_m, c.real[1].sd_m),
                                  std::hypot(model.east_m, model.north_m));
}

Subcommand add_calibrate_command(CLI::App& app) {
  auto args = std::make_shared<CalibrationArgs>();
  CLI::App* sub = add_calibration_subcommand(app, "calibrate", kHelp, args);
  sub->add_option("-o,--config-out", args->out,
                  "write the config here and the summary to stdout (default: config to stdout, summary "
                  "to stderr)")
      ->option_text("FILE");
  return {sub, [args](const Config& config, const std::atomic<bool>&) {
            const calibration::Calibration c = run_calibration(*args, config.receiver().seed);
            const calibration::ReceiverState state = learned_receiver_state(args->log, c);
            const std::string toml = calibration::config_toml(c, args->log) + calibration::receiver_state_toml(state);
            const std::string summary = calibration::log_summary(c, args->log) + calibration::receiver_state_summary(state) +
                                        calibration::calibration_summary(c);
            if (args->out.empty()) {
              std::fputs(toml.c_str(), stdout);
              std::fputs(summary.c_str(), stderr);
            } else {
              std::ofstream f(args->out);
              if (!f || !(f << toml) || !f.flush())
                throw std::runtime_error(fmt::format("-o: cannot write '{}'", args->out));
              std::fputs(summary.c_str(), stdout);
              std::fputs(fmt::format("config written to {}\n", args->out).c_str(), stdout);
            }
            return 0;
          }};
}

}  // namespace gpsemu
