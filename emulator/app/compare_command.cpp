// `gpsemu compare LOG`.
#include <cstdio>

#include <fmt/format.h>

#include "emulator/app/calibration_commands.hpp"
#include "emulator/calibration/report.hpp"
#include "emulator/config/config.hpp"

namespace gpsemu {

namespace {

constexpr const char* kHelp =
    "calibrate every noise model to a stationary receiver's NMEA log, simulate each at the log's "
    "rate, duration and resolution, and print real vs models side by side with a score";

}  // namespace

Subcommand add_compare_command(CLI::App& app) {
  auto args = std::make_shared<CalibrationArgs>();
  CLI::App* sub = add_calibration_subcommand(app, "compare", kHelp, args);
  sub->add_option("--csv", args->csv, "also write the real and each model's first simulated series (metres) as CSV")
      ->option_text("FILE");
  return {sub, [args](const Config& config, const std::atomic<bool>&) {
            const std::uint64_t seed = config.receiver().seed;
            const calibration::Calibration c = run_calibration(*args, seed);
            std::string out = calibration::log_summary(c, args->log);
            out += calibration::receiver_state_summary(learned_receiver_state(args->log, c));
            out += fmt::format("{} runs per model, seeds {}..{}; models simulated at the log's rate, length, "
                               "gaps and resolution; each run is a window of the log's length: the columns are the "
                               "median over the runs (what a typical run looks like), p10..p90 rows their spread\n",
                               args->runs, seed, seed + static_cast<std::uint64_t>(args->runs) - 1);
            out += calibration::comparison_table(c);
            std::fputs(out.c_str(), stdout);
            if (!args->csv.empty()) calibration::write_csv(c, args->csv);
            return 0;
          }};
}

}  // namespace gpsemu
