// What `gpsemu calibrate LOG` and `gpsemu compare LOG` print (see calibrate.hpp for what they
// compute): the log's summary, the fitted models' parameters and scores, the side-by-side table of
// statistics, and the series as CSV for plots. Plain text from a Calibration; the command-line glue
// is in emulator/app/.
#pragma once

#include <string>

#include "emulator/calibration/calibrate.hpp"

namespace gpsemu::calibration {

/// The log: fixes, rate, duration, resolution, mean position and what the reader skipped.
[[nodiscard]] std::string log_summary(const Calibration& c, const std::string& path);
/// The measured cgrw statistics against the fit, each model's parameters and the scores.
[[nodiscard]] std::string calibration_summary(const Calibration& c);
/// Real against every model, statistic by statistic and axis by axis, with the scores.
[[nodiscard]] std::string comparison_table(const Calibration& c);
/// The real and each model's first simulated series (metres) as CSV. Throws std::runtime_error
/// naming `path` when it cannot be written.
void write_csv(const Calibration& c, const std::string& path);

}  // namespace gpsemu::calibration
