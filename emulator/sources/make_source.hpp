// Builds the pose source named by --source.
#pragma once

#include <memory>

#include "emulator/config/config.hpp"
#include "emulator/sources/pose_source.hpp"

namespace gpsemu::sources {

/// Throws std::invalid_argument / std::runtime_error naming the source spec on failure.
[[nodiscard]] std::unique_ptr<PoseSource> make_source(const Config& config, const LocalFrame& frame,
                                                      UtcNs first_epoch);

}  // namespace gpsemu::sources
