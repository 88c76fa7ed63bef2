// A file descriptor owned by one object (closed when it goes), and reading and discarding what a
// descriptor has: the input clients write to an output (gpsd's probes), bounded per call.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
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
  int error = 0;
};

/// Reads what the non-blocking `fd` has, at most about `limit_bytes` (bounds one call), handing
/// each chunk to `consume` (an output's client input: transport/output.hpp) or, without one,
/// discarding it; never blocks.
[[nodiscard]] Drained drain_input(int fd, std::size_t limit_bytes,
                                  const std::function<void(std::string_view)>& consume = {});

}  // namespace gpsemu::posix
