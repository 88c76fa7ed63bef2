// A pseudo-terminal that looks like a GPS receiver's serial port: clients (gpsd, a ROS NMEA driver,
// an autopilot) open /dev/pts/N, or a stable symlink to it, and read NMEA; what they write goes to
// the receiver's client input (a u-blox answers it) or is discarded. The emulator keeps its own
// slave descriptor open, so a client closing and reopening the device never hangs the pty up.
//
// What the pty holds is a queue of whole messages (epochs, answers) in the order written; what
// it cannot take yet waits here (at most max_waiting_bytes), behind whatever is queued, and goes
// out as the client reads. Nothing a client is reading is ever discarded: an answer never
// flushes anything. A client never receives a backlog of old epochs: when nobody read anything
// for a whole epoch period (no client, or one that stopped reading), or when every client has
// closed the device (inotify), what is queued is discarded and counted. Every client closing it
// also ends the connection: the next one to open it starts with a fresh frame reader.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <filesystem>
#include <optional>
#include <string>

#include "transport/output.hpp"
#include "transport/posix/open_watch.hpp"

namespace gpsemu::transport {

/// Counters specific to a pty, next to the base class's Output::stats().
struct PtyStats {
  std::uint64_t stale_epochs_discarded = 0;  ///< times queued epochs (or their tails) no client read were discarded
  std::uint64_t stale_bytes_discarded = 0;   ///< bytes of those, as the kernel reported them, and waiting here
  std::uint64_t input_bytes_discarded = 0;   ///< bytes clients wrote to us (probes), read and dropped
  std::uint64_t clients_left = 0;            ///< times every client had closed the device
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

  /// Bytes waiting here for room in the pty at most; a further epoch or answer is dropped whole.
  static constexpr std::size_t max_waiting_bytes = 64 * 1024;

  /// Reads client input, notices every client closing the device, sends what waits for room.
  void service() override;
  /// Discards what no client read for a whole period (else the next write does it first).
  void prepare_epoch() override;
  /// Readable on client input, on clients opening or closing the device, and (while bytes wait
  /// here) when the pty has room.
  [[nodiscard]] int poll_fd() const override { return epoll_fd_; }
  /// "/dev/pts/5 (link /tmp/gpsemu)" or "/dev/pts/5".
  [[nodiscard]] std::string describe() const override;

  /// The slave device clients open, e.g. /dev/pts/5.
  [[nodiscard]] const std::filesystem::path& device_path() const { return device_path_; }
  /// The stable symlink to device_path(), if one was requested.
  [[nodiscard]] const std::optional<std::filesystem::path>& link_path() const { return link_; }
  [[nodiscard]] const PtyStats& pty_stats() const { return pty_stats_; }
  /// Descriptors clients have open on the device now, as its open watch tells (empty without one).
  [[nodiscard]] std::optional<std::uint64_t> clients_open() const {
    return opens_ && opens_->valid() ? std::optional<std::uint64_t>(opens_->open_count()) : std::nullopt;
  }
  [[nodiscard]] std::optional<std::uint64_t> clients_connected() const override { return clients_open(); }

 protected:
  WriteStatus write_bytes(std::string_view bytes, std::string& error_text) override;
  /// An answer, to the client that has the device open now (else it has gone: dropped).
  WriteStatus write_reply(ClientId client, std::string_view bytes, std::string& error_text) override;

 private:
  /// A message not yet (wholly) taken by the pty.
  struct Waiting {
    std::string bytes;
    std::size_t sent = 0;  ///< its first bytes already in the pty
    bool epoch = false;
  };
  void open_pty();
  void open_watches();
  void create_link();
  /// Discards what no client read since the last call (a whole period), if anything.
  void discard_stale_input();
  /// Discards everything queued, in the pty and waiting here (counted).
  void discard_all(int unread);
  /// Reads the open watch: every client closed the device -> a new connection.
  void notice_clients();
  /// No client has the device open, as far as the open watch has told (false without one).
  [[nodiscard]] bool nobody_open() const { return opens_ && opens_->valid() && opens_->open_count() == 0; }
  /// Queues `bytes` behind what is queued: ok, dropped (no room: nothing of it went out) or error.
  WriteStatus send(std::string_view bytes, bool epoch, std::string& error_text);
  /// Writes what waits while the pty takes it.
  void send_waiting();
  void watch_room(bool on);
  [[nodiscard]] int unread() const;
  void close_fds() noexcept;
  void report_discards();

  std::optional<std::filesystem::path> link_;
  std::filesystem::path device_path_;
  int master_fd_ = -1;
  int slave_fd_ = -1;  ///< held open for our lifetime so a client's close never hangs up the pty
  int epoll_fd_ = -1;  ///< master (input; room while bytes wait) and the open watch
  std::unique_ptr<posix::OpenWatch> opens_;
  ClientId client_ = new_client_id();  ///< whoever has the device open now
  std::deque<Waiting> waiting_;
  std::size_t waiting_bytes_ = 0;
  bool watching_room_ = false;
  std::uint64_t taken_ = 0;           ///< bytes the pty took, in all
  std::uint64_t taken_at_check_ = 0;  ///< at the last discard_stale_input()
  std::uint64_t epoch_bytes_taken_ = 0;           ///< of taken_, the epochs' (the rest: answers)
  std::uint64_t epoch_bytes_taken_at_check_ = 0;  ///< at the last discard_stale_input()
  int unread_at_check_ = 0;           ///< unread bytes then
  bool taken_unopened_ = false;       ///< the pty took bytes while nobody had it open, since then
  PtyStats pty_stats_;
  PtyStats reported_;  ///< counters at the last log line, to log differences at most once a second
  LogLimit discard_log_{1};     ///< the discard lines (debug): at most one a second
  LogLimit read_error_log_{1};  ///< "reading client input failed": at most one a second
  bool prepared_ = false;  ///< prepare_epoch() ran since the last write
};

}  // namespace gpsemu::transport
