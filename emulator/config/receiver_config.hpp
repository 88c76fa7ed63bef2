// From a Config to what the receiver model and the outputs need at start-up: the receiver options
// with the noise model's measured sigma and the run's seed, and the serial line budget of the
// configured sentences (for outputs with a baud rate: refuse a configuration that cannot fit).
#pragma once

#include "emulator/config/config.hpp"
#include "emulator/model/receiver.hpp"
#include "nmea/line_budget.hpp"

namespace gpsemu {

/// config.receiver with noise_sigma_m = estimate_noise_sigma_m(config.noise, config.seed) and
/// sky_seed = config.seed. Throws std::invalid_argument for a bad noise configuration.
[[nodiscard]] ReceiverOptions receiver_options(const Config& config);

/// Bytes per epoch, bytes per second and minimum baud of config.format.sentences at config.rate_hz
/// with the receiver's satellites in view (nmea::line_budget). Compare with a line's baud via
/// LineBudget::fits; nmea::smallest_standard_baud names the baud that would fit.
[[nodiscard]] nmea::LineBudget line_budget(const Config& config);

}  // namespace gpsemu
