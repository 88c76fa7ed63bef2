#include "transport/posix/fd.hpp"

#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>

namespace gpsemu::posix {

void UniqueFd::reset(int fd) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
}

Drained drain_input(int fd, InputBudget budget, const std::function<void(std::string_view)>& consume) {
  std::array<char, 4096> buf{};
  // Input that is worked on (a u-blox's configuration) is read in small pieces, so the time budget
  // bounds the work; input that is dropped is read in big ones.
  const std::size_t piece = consume ? 1024 : buf.size();
  const bool timed = budget.time != std::chrono::nanoseconds::max();
  const auto begin = timed ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  Drained d;
  while (true) {
    if (d.bytes >= budget.bytes || (timed && d.bytes > 0 && std::chrono::steady_clock::now() - begin >= budget.time)) {
      d.limited = true;
      break;
    }
    const ssize_t n = ::read(fd, buf.data(), piece);
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
