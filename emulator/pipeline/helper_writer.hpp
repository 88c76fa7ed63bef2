// A second writer thread for many receivers in one process (epoch_loop.hpp): it writes one part of
// the outputs while the loop's thread writes the other, both from the same instant, so the
// burst of writes after an epoch's deadline is half as long (a loopback UDP datagram costs the
// sender ~9 us: 256 of them take 2-2.5 ms in one thread). It is handed an epoch once every text
// is formatted, sleeps until the write time on its own (its own posix::Waiter), writes,
// and says when it is done. It inherits the scheduling of the thread that makes it (SCHED_FIFO
// when the loop was given a real-time priority).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

#include "emulator/model/time.hpp"

namespace gpsemu {

class HelperWriter {
 public:
  /// `write(first, from, to)`: write the channels at positions [from, to) of the order that
  /// starts with channel `first` (called on the helper thread).
  using WriteFn = std::function<void(std::size_t first, std::size_t from, std::size_t to)>;

  explicit HelperWriter(WriteFn write);
  /// Finishes the epoch in hand, if any, and joins the thread.
  ~HelperWriter();
  HelperWriter(const HelperWriter&) = delete;
  HelperWriter& operator=(const HelperWriter&) = delete;

  /// Writes positions [from, to) of the order starting with `first` at `write_at` (wall clock);
  /// not at all when woken after `latest` (the process was stopped: the epoch is skipped).
  void post(UtcNs write_at, std::size_t first, std::size_t from, std::size_t to, UtcNs latest = UtcNs::max());
  /// Waits until the posted epoch is written.
  void wait_done();

 private:
  struct Job {
    UtcNs write_at;
    std::size_t first, from, to;
    UtcNs latest;
  };
  void loop();

  WriteFn write_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::optional<Job> job_;
  bool busy_ = false;
  bool quit_ = false;
  std::thread thread_;  ///< last: started once everything above is ready
};

}  // namespace gpsemu
