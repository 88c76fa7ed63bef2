// From a receiver's settings to what the receiver model, its pose source and the outputs need at
// start-up: the receiver options with the noise model's measured sigma and the receiver's seed,
// the pose source, and the serial line budget of the configured sentences (for outputs with a
// baud rate: refuse a configuration that cannot fit).
#pragma once

#include <memory>

#include "emulator/config/settings.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/sources/pose_source.hpp"
#include "nmea/line_budget.hpp"

namespace gpsemu {

/// receiver.model with noise_sigma_m = estimate_noise_sigma_m(receiver.noise, receiver.seed)
/// and sky_seed = receiver.seed. Throws std::invalid_argument for a bad noise configuration.
[[nodiscard]] ReceiverOptions receiver_options(const ReceiverSettings& receiver);

/// The receiver's pose source (sources::make_source) on `timeline` (lockstep: poses placed at
/// --start-time or `first_epoch` + their t), its first epoch at `first_epoch`.
[[nodiscard]] std::unique_ptr<sources::PoseSource> make_receiver_source(const ReceiverSettings& receiver,
                                                                        const TimelineSettings& timeline,
                                                                        const LocalFrame& frame, UtcNs first_epoch);

/// Bytes per epoch, bytes per second and minimum baud of receiver.format.sentences at `rate_hz`
/// with the receiver's satellites in view (nmea::line_budget). Compare with a line's baud via
/// LineBudget::fits; nmea::smallest_standard_baud names the baud that would fit.
[[nodiscard]] nmea::LineBudget line_budget(const ReceiverSettings& receiver, double rate_hz);

}  // namespace gpsemu
