// Between the epoch loop and whoever watches it: the bench view's HTTP server (its own threads,
// emulator/ui/http_server.hpp), `gpsemu ctl PATH watch` (the control socket) and the periodic
// status line. The loop tells the hub every receiver's epoch (EpochObserver) and, only while
// somebody watches that receiver, the hub renders the epoch's JSON (snapshot.hpp) and publishes it:
// a shared_ptr swapped under a mutex that nobody holds for longer than that swap, so the loop
// never waits for a browser. The server's fault requests come back through the hub as a loop
// input (an eventfd): the loop answers them between epochs with the control socket's own
// protocol (faults/control.hpp), so a click is a live fault like `gpsemu ctl` (and is in --tee).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "emulator/faults/control.hpp"
#include "emulator/pipeline/channel_set.hpp"
#include "emulator/pipeline/control_socket.hpp"
#include "emulator/ui/snapshot.hpp"
#include "transport/posix/fd.hpp"

namespace gpsemu::ui {

class Hub final : public LoopInput, public EpochObserver {
 public:
  /// `status_every`: a status line in the log this often (zero: never).
  Hub(ChannelSet& channels, std::chrono::nanoseconds status_every);
  ~Hub() override;
  Hub(const Hub&) = delete;
  Hub& operator=(const Hub&) = delete;

  // --- the loop's thread ---
  void epoch(const EpochView& view) override;
  void fds(std::vector<int>& out) const override;
  /// Fault requests answered a call of service() at most (the rest at the loop's next wake-up).
  static constexpr std::size_t kRequestsPerService = 4;
  /// Answers the requests the server queued (kRequestsPerService of them; more wake the loop again).
  void service() override;
  /// `gpsemu ctl PATH watch` clients are this control socket's (may be null).
  void set_control_socket(ControlSocket* control) { control_socket_ = control; }
  /// ctl status's additions for receiver i: HDOP, satellites in view, the error against the
  /// truth, the outputs and their clients, the page's and the watchers' clients.
  [[nodiscard]] std::string status_extra(std::size_t i) const;
  /// Where the loop counts its late epochs (LoopOptions::late_epochs).
  [[nodiscard]] std::atomic<std::uint64_t>& late_epochs() { return late_epochs_; }

  // --- any thread ---
  struct Published {
    std::uint64_t epoch = 0;  ///< the receiver's epochs when it was published (0: none yet)
    std::shared_ptr<const std::string> json;
  };
  /// Receiver i's last published epoch, or, with `after`, the first one after that epoch (waits
  /// at most `timeout`; empty json when none came or the hub closed).
  [[nodiscard]] Published wait_after(std::size_t i, std::uint64_t after, std::chrono::milliseconds timeout) const;
  /// A page starts (+1) or stops (-1) watching receiver i: epochs are rendered while any does.
  void watch(std::size_t i, int delta);
  [[nodiscard]] std::size_t page_clients() const;
  /// One control request (faults/control.hpp's JSON line) answered by the loop between epochs;
  /// empty when the loop did not take it within `timeout` (stopping, or --fast between services).
  [[nodiscard]] std::optional<std::string> request(std::string line, std::chrono::milliseconds timeout);
  /// The loop has stopped: waiting pages are woken, requests are refused.
  void close();
  [[nodiscard]] bool closed() const;
  [[nodiscard]] std::size_t receivers() const { return receivers_.size(); }
  /// {"receivers":N,"names":[...],"faults":[{"fault":"jam","parameters":[{"key","help"}]...}]}: what the page builds its
  /// selector and fault forms from.
  [[nodiscard]] const std::string& info_json() const { return info_json_; }

 private:
  struct Receiver {
    Published published;
    int page_clients = 0;
    std::uint64_t epochs = 0;
    // The last epoch in brief (ctl status, the status line).
    EpochError error;
    double hdop = 0.0;
    int satellites_used = 0, satellites_in_view = 0;
    nmea::FixQuality quality = nmea::FixQuality::none;
    const std::vector<std::unique_ptr<transport::Output>>* outputs = nullptr;
    // bytes a second: the outputs' bytes at the start of the window and its start
    std::uint64_t window_bytes = 0;
    UtcNs window_start{};
    double bytes_per_s = 0.0;
    std::chrono::steady_clock::time_point last_status_line{};
  };
  struct Pending {
    std::string line;
    std::promise<std::string> answer;
  };
  void log_status_line(std::size_t i, const Receiver& r, const Channel& channel) const;

  ChannelSet& channels_;
  faults::FaultControl control_;
  std::chrono::nanoseconds status_every_;
  ControlSocket* control_socket_ = nullptr;
  std::atomic<std::uint64_t> late_epochs_{0};
  std::string info_json_;
  posix::UniqueFd wake_;  ///< eventfd: a request is queued

  mutable std::mutex mutex_;  ///< guards what follows
  mutable std::condition_variable published_;
  std::vector<Receiver> receivers_;
  std::deque<std::shared_ptr<Pending>> pending_;
  bool closed_ = false;
};

}  // namespace gpsemu::ui
