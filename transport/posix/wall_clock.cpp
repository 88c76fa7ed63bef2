#include "transport/posix/wall_clock.hpp"

namespace gpsemu::posix {

WallTime wall_clock_now() {
  timespec ts{};
  ::clock_gettime(CLOCK_REALTIME, &ts);
  return to_wall_time(ts);
}

}  // namespace gpsemu::posix
