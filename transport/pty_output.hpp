// A pseudo-terminal that looks like a GPS receiver's serial port: clients (gpsd, a ROS NMEA driver,
// an autopilot) open /dev/pts/N, or a stable symlink to it, and read NMEA; whatever they write is
// read and discarded. The emulator keeps its own slave descriptor open, so a client closing and
// reopening the device never hangs the pty up, and a client never receives a backlog of old
// epochs: unread bytes of earlier epochs are discarded before each new epoch goes out.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "transport/output.hpp"

namespace gpsemu::transport {

/// Counters specific to a pty, next to the base class's Output::stats().
struct PtyStats {
  std::uint64_t stale_epochs_discarded = 0;  ///< epochs (or their tails) no client read in time
  std::uint64_t stale_bytes_discarded = 0;   ///< bytes of those epochs, as the kernel reported them
  std::uint64_t input_bytes_discarded = 0;   ///< bytes clients wrote to us (probes), read and dropped
};

class PtyOutput final : public Output {
 public:
  /// Opens a new pty in raw mode. With `link`, also creates the symlink `link` -> /dev/pts/N,
  /// replacing a symlink left there by an earlier run, and marks the pty as serving `link` (a lock
  /// on its slave side, gone when this process ends however it ends). Throws std::runtime_error
  /// naming the path when the pty cannot be created, when `link` exists and is not a symlink,
  /// when `link` points to the pty of another gpsemu still running with that link, or when the
  /// directory of `link` does not exist.
  explicit PtyOutput(std::optional<std::filesystem::path> link = std::nullopt);
  /// Removes the symlink if it still points to this pty, then closes both sides.
  ~PtyOutput() override;

  void service() override;
  /// Discards what no client read (else the next write does it first).
  void prepare_epoch() override;
  [[nodiscard]] int poll_fd() const override { return master_fd_; }
  /// "/dev/pts/5 (link /tmp/gpsemu)" or "/dev/pts/5".
  [[nodiscard]] std::string describe() const override;

  /// The slave device clients open, e.g. /dev/pts/5.
  [[nodiscard]] const std::filesystem::path& device_path() const { return device_path_; }
  /// The stable symlink to device_path(), if one was requested.
  [[nodiscard]] const std::optional<std::filesystem::path>& link_path() const { return link_; }
  [[nodiscard]] const PtyStats& pty_stats() const { return pty_stats_; }

 protected:
  WriteStatus write_bytes(std::string_view bytes, std::string& error_text) override;

 private:
  void open_pty();
  void create_link();
  void discard_stale_input();
  void close_fds() noexcept;
  void report_discards();

  std::optional<std::filesystem::path> link_;
  std::filesystem::path device_path_;
  int master_fd_ = -1;
  int slave_fd_ = -1;  ///< held open for our lifetime so a client's close never hangs up the pty
  PtyStats pty_stats_;
  PtyStats reported_;  ///< counters at the last log line, to log differences at most once a second
  std::chrono::steady_clock::time_point last_report_{};
  std::chrono::steady_clock::time_point last_service_error_{};
  bool prepared_ = false;  ///< prepare_epoch() ran since the last write
};

}  // namespace gpsemu::transport
