// Test support: open a pty (its /dev/pts/N or a link to it) as a client does, in raw mode and
// non-blocking, so what the emulator writes reads back byte for byte.
#pragma once

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <filesystem>

namespace gpsemu::test {

/// The client's descriptor, or -1.
inline int open_raw_pty_client(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return -1;
  termios tio{};
  if (::tcgetattr(fd, &tio) == 0) {
    ::cfmakeraw(&tio);
    ::tcsetattr(fd, TCSANOW, &tio);
  }
  return fd;
}

}  // namespace gpsemu::test
