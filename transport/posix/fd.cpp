#include "transport/posix/fd.hpp"

#include <unistd.h>

#include <array>
#include <cerrno>

namespace gpsemu::posix {

void UniqueFd::reset(int fd) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
}

Drained drain_input(int fd, std::size_t limit_bytes, const std::function<void(std::string_view)>& consume) {
  std::array<char, 4096> buf{};
  Drained d;
  while (d.bytes < limit_bytes) {
    const ssize_t n = ::read(fd, buf.data(), buf.size());
    if (n > 0) {
      d.bytes += static_cast<std::uint64_t>(n);
      if (consume) consume({buf.data(), static_cast<std::size_t>(n)});
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    d.end = n == 0 ? Drained::End::closed : Drained::End::failed;
    d.error = n == 0 ? 0 : errno;
    break;
  }
  return d;
}

}  // namespace gpsemu::posix
