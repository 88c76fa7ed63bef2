// Who has a device node open: inotify's IN_OPEN and IN_CLOSE_* events on one path (a pty's
// /dev/pts/N), counted, so an output learns when every client of its pty has closed it (the next
// one to open it is a new client: its half-written input and the unread output are not its own).
// Opens and closes of the node by any path (a symlink included) count; descriptors opened before
// the watch (the emulator's own) do not.
#pragma once

#include <cstdint>
#include <filesystem>

#include "transport/posix/fd.hpp"

namespace gpsemu::posix {

class OpenWatch {
 public:
  /// Watches `path`. Without inotify (or when the watch fails) valid() is false and nothing is seen.
  explicit OpenWatch(const std::filesystem::path& path);

  [[nodiscard]] bool valid() const { return fd_.valid(); }
  /// Readable when events wait (-1 when not valid()).
  [[nodiscard]] int fd() const { return fd_.get(); }

  struct Events {
    std::uint64_t opens = 0;
    std::uint64_t closes = 0;
    bool all_closed = false;  ///< at some point of these events nobody had it open (after someone had)
    bool overflow = false;    ///< the kernel dropped events: the count starts again from none open
  };
  /// The events since the last call, in their order (never blocks).
  [[nodiscard]] Events read_events();
  /// Descriptors open on the node now, as far as the events tell.
  [[nodiscard]] std::uint64_t open_count() const { return open_; }

 private:
  UniqueFd fd_;
  std::uint64_t open_ = 0;
};

}  // namespace gpsemu::posix
