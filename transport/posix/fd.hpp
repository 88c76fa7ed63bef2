// A file descriptor owned by one object (closed when it goes), and reading and discarding what a
// descriptor has: the input clients write to an output (gpsd's probes), bounded per call.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>

namespace gpsemu::posix {

/// Owns a descriptor: move-only, closes it on destruction or reset(). -1 means none.
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  ~UniqueFd() { reset(); }
  UniqueFd(UniqueFd&& other) noexcept : fd_(other.release()) {}
  UniqueFd& operator=(UniqueFd&& other) noexcept {
    if (this != &other) reset(other.release());
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;

  /// Closes the owned descriptor (if any) and owns `fd` instead.
  void reset(int fd = -1);
  /// Gives up ownership: returns the descriptor, which the caller now closes.
  [[nodiscard]] int release() { return std::exchange(fd_, -1); }
  [[nodiscard]] int get() const { return fd_; }
  [[nodiscard]] bool valid() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

/// What drain_input() found.
struct Drained {
  enum class End {
    empty,   ///< nothing more to read now (EAGAIN), or the limit was reached
    closed,  ///< end of file: the other side hung up
    failed,  ///< a read error other than EAGAIN/EINTR; `error` holds its errno
  };
  std::uint64_t bytes = 0;  ///< bytes read and discarded
  End end = End::empty;
  bool limited = false;  ///< stopped by the byte or time budget: more may be waiting in the kernel
  int error = 0;
};

/// What one call of drain_input() may do: read at most `bytes` (about: whole reads), and start no
/// read after `time` has passed since the call began. What is left stays in the kernel for the
/// next call, so a client's burst never holds the loop up for more than about one budget.
struct InputBudget {
  std::size_t bytes = 1 << 20;
  std::chrono::nanoseconds time = std::chrono::nanoseconds::max();
};

/// Reads what the non-blocking `fd` has, within `budget`, handing each chunk to `consume` (an
/// output's client input: transport/output.hpp; reads of at most 1 KiB then, so the time budget
/// is checked between small pieces of work) or, without one, discarding it; never blocks.
[[nodiscard]] Drained drain_input(int fd, InputBudget budget,
                                  const std::function<void(std::string_view)>& consume = {});
/// The same with a byte budget alone.
[[nodiscard]] inline Drained drain_input(int fd, std::size_t limit_bytes,
                                         const std::function<void(std::string_view)>& consume = {}) {
  return drain_input(fd, InputBudget{.bytes = limit_bytes}, consume);
}

/// Replaces the file at `path` with `text` whole or not at all, safely in a directory others may
/// write to (gpsemu may run as root): the text goes to a new temporary file of its own in the
/// same directory (mkstemp: O_EXCL, never through a link someone put there), is flushed, and is
/// renamed over `path` (rename replaces a link at `path` itself, never its target). False with
/// `error` set when it cannot (the temporary is removed).
bool replace_file(const std::string& path, std::string_view text, std::string& error);

}  // namespace gpsemu::posix
