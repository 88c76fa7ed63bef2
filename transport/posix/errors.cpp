#include "transport/posix/errors.hpp"

#include <system_error>

namespace gpsemu::posix {

std::string errno_text(int err) { return std::generic_category().message(err); }

}  // namespace gpsemu::posix
