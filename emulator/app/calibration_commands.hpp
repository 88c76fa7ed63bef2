// `gpsemu calibrate LOG` and `gpsemu compare LOG` (calibration/calibrate.hpp computes, report.hpp
// prints). calibrate writes the config file (to -o FILE, or to standard output with the summary on
// standard error) and prints a summary; compare prints the log and every calibrated model side by
// side with their scores, and can write the series as CSV for plots. Both take --seed.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "emulator/app/subcommands.hpp"
#include "emulator/calibration/calibrate.hpp"
#include "emulator/calibration/receiver_state.hpp"

namespace gpsemu {

/// The arguments both subcommands take.
struct CalibrationArgs {
  std::string log;   ///< the stationary receiver's NMEA log
  std::string out;   ///< calibrate: config file; empty = stdout
  std::string csv;   ///< compare: series for plots
  std::string json;  ///< judge: scores as JSON
  std::string plots; ///< judge: directory for the CSV files of tools/plot_noise.py
  int runs = 32;     ///< simulated runs per model, seeds seed, seed+1, ...
  bool detrend = false;  ///< remove a smooth trajectory instead of refusing a log that moves
};

/// Adds the subcommand `name` to `app` with LOG and --runs, stored in `args`.
[[nodiscard]] CLI::App* add_calibration_subcommand(CLI::App& app, const std::string& name, const std::string& description,
                                                   const std::shared_ptr<CalibrationArgs>& args);
/// The options of `args` with runs seeded from `seed`, and at most the epochs the memory
/// available now holds (MemAvailable of /proc/meminfo; kMaxCalibrationEpochs without it).
[[nodiscard]] calibration::CalibrateOptions calibration_options(const CalibrationArgs& args, std::uint64_t seed);
/// Reads the log and calibrates every model, runs seeded from `seed`.
[[nodiscard]] calibration::Calibration run_calibration(const CalibrationArgs& args, std::uint64_t seed);

/// The log's receiver state (satellites, DOPs, C/N0, mask, UERE from the calibration's horizontal
/// sigma): calibration/receiver_state.hpp.
[[nodiscard]] calibration::ReceiverState learned_receiver_state(const std::string& log, const calibration::Calibration& c);

[[nodiscard]] Subcommand add_calibrate_command(CLI::App& app);  // calibrate_command.cpp
[[nodiscard]] Subcommand add_compare_command(CLI::App& app);    // compare_command.cpp
[[nodiscard]] Subcommand add_judge_command(CLI::App& app);      // judge_command.cpp

}  // namespace gpsemu
