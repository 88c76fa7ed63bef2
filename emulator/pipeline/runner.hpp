// The main loop: for each epoch on the UTC grid, sample the pose source, run the receiver model,
// format the sentences and hand them to every output at epoch time + latency (or as fast as
// possible with --fast). Absolute deadlines, so nothing drifts. With a PPS line, its edges and
// the epoch writes share one timeline: leading edge at each whole second S, the NMEA stamped S
// at S + latency after it, trailing edge at S + width.
//
// Many receivers (fleet_config.hpp) run on that one timeline, each with its own source, noise
// and outputs. The runner computes and formats every receiver's epoch ahead of the deadline (by
// a lead that follows the measured cost of doing so, never earlier than the epoch's own time),
// so at the deadline only the writes are left; from 8 receivers on, a second thread writes half
// of them from the same instant, in an order that rotates every epoch so no receiver is always
// last. One receiver runs exactly as before: sampled, formatted and written at the deadline.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emulator/pipeline/clock.hpp"
#include "emulator/config/config.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/pipeline/helper_writer.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/sources/pose_source.hpp"
#include "emulator/model/time.hpp"
#include "transport/output.hpp"
#include "transport/pps.hpp"

namespace gpsemu {

struct RunStats {
  std::uint64_t epochs_emitted = 0;   ///< epochs formatted and handed to the outputs (each receiver's)
  std::uint64_t epochs_late_skipped = 0;  ///< epochs skipped because their time had long passed
  std::uint64_t epochs_without_fix = 0;   ///< over all receivers
  /// poll() wake-ups while waiting: one an epoch (plus one a PPS edge) when no input arrives.
  std::uint64_t wakeups = 0;
  std::uint64_t pps_pulses = 0;               ///< leading edges driven
  std::uint64_t pps_pulses_late_skipped = 0;  ///< pulses not sent: their second had passed by over half the width
  /// Worst time from a leading edge's whole second to the return of the call that drove it.
  std::chrono::nanoseconds pps_worst_edge_delay{0};
};

/// One receiver's counts (a fleet's summary has one line per receiver).
struct ReceiverStats {
  std::uint64_t epochs_emitted = 0;
  std::uint64_t epochs_without_fix = 0;
};

/// What a Runner writes to when the caller (a test) provides it instead of config.outputs/pps.
struct RunnerIo {
  std::vector<std::unique_ptr<transport::Output>> outputs;
  std::unique_ptr<transport::PpsLine> pps;  ///< none: no PPS
};

class Runner {
 public:
  /// Opens every receiver's source and outputs (receiver_configs(config)). Throws (std::exception
  /// with a clear message) when any of them cannot be set up: the caller exits with status 2.
  explicit Runner(const Config& config);
  /// One receiver writing to `io` instead of opening config.outputs and config.pps (tests:
  /// recording fakes).
  Runner(const Config& config, RunnerIo io);
  ~Runner();

  /// Runs until the duration is reached or `stop` becomes true. Returns the process exit status.
  int run(const std::atomic<bool>& stop);

  [[nodiscard]] const RunStats& stats() const { return stats_; }
  [[nodiscard]] std::size_t receivers() const { return channels_.size(); }
  [[nodiscard]] const ReceiverStats& receiver_stats(std::size_t i) const { return channels_.at(i)->stats; }
  /// Receiver i's outputs.
  [[nodiscard]] const std::vector<std::unique_ptr<transport::Output>>& outputs(std::size_t i = 0) const {
    return channels_.at(i)->outputs;
  }
  /// Epoch time minus wall time: 0, or the --start-time shift (whole seconds when PPS is on).
  [[nodiscard]] std::chrono::nanoseconds epoch_minus_wall() const { return sim_minus_wall_; }

 private:
  /// One receiver: its settings, frame, source, model, outputs and the text of its epoch.
  struct Channel {
    explicit Channel(ReceiverSettings c) : config(std::move(c)), frame(config.origin) {}
    ReceiverSettings config;
    LocalFrame frame;
    std::unique_ptr<sources::PoseSource> source;
    std::unique_ptr<Receiver> receiver;
    std::vector<std::unique_ptr<transport::Output>> outputs;
    std::string text;
    bool ended = false;  ///< its source has no truth from now on: nothing more is written
    ReceiverStats stats;
  };
  /// A descriptor the clock polls, and whose it is.
  struct Pollable {
    transport::Output* output = nullptr;
    sources::PoseSource* source = nullptr;
  };

  void init(std::optional<RunnerIo> io);
  void open_outputs(Channel& ch);
  void open_pps();
  /// Drives every PPS edge due at or before `wall_deadline`, each at its time.
  void run_pps_until(UtcNs wall_deadline, const std::atomic<bool>& stop);
  void wait_until(UtcNs wall_deadline, const std::atomic<bool>& stop) { clock_io_->sleep_until(wall_deadline, stop); }
  /// Samples, runs and formats `ch`'s epoch `t` into ch.text (prepare_epoch() on its outputs too
  /// when `prepare_outputs`).
  void compute(Channel& ch, UtcNs t, bool prepare_outputs);
  void write(Channel& ch);
  /// Writes positions [from, to) of the receivers in the order that starts with receiver `first`.
  void write_range(std::size_t first, std::size_t from, std::size_t to);
  /// Many receivers in real time: compute ahead of the deadline, write at it. False when stopped.
  bool run_fleet_epoch(std::int64_t k, UtcNs t, UtcNs deadline, const std::atomic<bool>& stop);
  void service_all();
  void log_summary() const;

  Config config_;
  EpochGrid grid_;
  std::int64_t first_index_ = 0;
  std::chrono::nanoseconds sim_minus_wall_{0};  ///< epoch time minus wall time (--start-time in real time)
  std::vector<std::unique_ptr<Channel>> channels_;  ///< not moved: a receiver refers to its frame
  std::unique_ptr<sources::PoseSource> fleet_time_;  ///< lockstep with many receivers: the slowest simulator's time
  std::vector<Pollable> pollables_;                  ///< what the clock's k-th descriptor belongs to
  std::unique_ptr<SystemClockIo> clock_io_;  ///< every wait: one poll() over a timerfd and the inputs
  std::unique_ptr<transport::PpsLine> pps_;  ///< after the outputs: a modem PPS line uses a serial output
  std::chrono::nanoseconds pps_width_{0};
  transport::PpsEdge next_edge_{};
  std::chrono::steady_clock::time_point last_pps_warning_{};
  /// Many receivers: how long computing every epoch took lately (decaying maximum).
  std::chrono::nanoseconds compute_cost_{0};
  std::unique_ptr<HelperWriter> helper_;  ///< last: stopped before the channels it writes go
  RunStats stats_;
};

}  // namespace gpsemu
