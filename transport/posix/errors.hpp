// Error text of the operating system's calls, for messages a user reads.
#pragma once

#include <string>

namespace gpsemu::posix {

/// The system's text for an errno value ("No such file or directory").
[[nodiscard]] std::string errno_text(int err);

}  // namespace gpsemu::posix
