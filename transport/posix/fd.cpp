#include "transport/posix/fd.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include <array>
#include <cerrno>
#include <cstring>
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

bool replace_file(const std::string& path, std::string_view text, std::string& error) {
  const std::size_t slash = path.rfind('/');
  const std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  std::string temporary = dir + "/." + base + ".XXXXXX";
  UniqueFd fd(::mkostemp(temporary.data(), O_CLOEXEC));
  if (!fd.valid()) {
    error = "cannot create a temporary file in " + dir + ": " + std::string(std::strerror(errno));
    return false;
  }
  const auto fail = [&](const std::string& what) {
    error = what + ": " + std::string(std::strerror(errno));
    ::unlink(temporary.c_str());
    return false;
  };
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd.get(), text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return fail("cannot write " + temporary);
    done += static_cast<std::size_t>(n);
  }
  (void)::fchmod(fd.get(), 0644);
  if (::fsync(fd.get()) != 0) return fail("cannot flush " + temporary);
  fd.reset();
  if (::rename(temporary.c_str(), path.c_str()) != 0) return fail("cannot rename " + temporary + " to " + path);
  return true;
}

}  // namespace gpsemu::posix
