#include "transport/posix/open_watch.hpp"

#include <sys/inotify.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

namespace gpsemu::posix {

OpenWatch::OpenWatch(const std::filesystem::path& path) : fd_(::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) {
  if (!fd_.valid()) return;
  if (::inotify_add_watch(fd_.get(), path.c_str(), IN_OPEN | IN_CLOSE_WRITE | IN_CLOSE_NOWRITE) < 0) fd_.reset();
}

OpenWatch::Events OpenWatch::read_events() {
  Events events;
  if (!fd_.valid()) return events;
  alignas(inotify_event) std::array<char, 4096> buf{};
  for (;;) {
    const ssize_t n = ::read(fd_.get(), buf.data(), buf.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    for (std::size_t at = 0; at + sizeof(inotify_event) <= static_cast<std::size_t>(n);) {
      inotify_event e{};
      std::memcpy(&e, buf.data() + at, sizeof e);
      if ((e.mask & IN_OPEN) != 0) {
        ++events.opens;
        ++open_;
      }
      if ((e.mask & (IN_CLOSE_WRITE | IN_CLOSE_NOWRITE)) != 0) {
        ++events.closes;
        if (open_ > 0) --open_;
        if (open_ == 0) events.all_closed = true;
      }
      if ((e.mask & IN_Q_OVERFLOW) != 0) {
        events.overflow = true;
        events.all_closed = true;  // unknown: take it as a new start
        open_ = 0;
      }
      at += sizeof(inotify_event) + e.len;
    }
  }
  return events;
}

}  // namespace gpsemu::posix
