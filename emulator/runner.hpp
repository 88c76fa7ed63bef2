// The main loop: for each epoch on the UTC grid, sample the pose source, run the receiver model,
// format the sentences and hand them to every output at epoch time + latency (or as fast as
// possible with --fast). Absolute deadlines, so nothing drifts. With a PPS line, its edges and
// the epoch writes share one timeline: leading edge at each whole second S, the NMEA stamped S
// at S + latency after it, trailing edge at S + width.
#pragma once

#include <poll.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "emulator/config.hpp"
#include "emulator/geo.hpp"
#include "emulator/receiver.hpp"
#include "emulator/sources/pose_source.hpp"
#include "emulator/time.hpp"
#include "transport/output.hpp"
#include "transport/pps.hpp"

namespace gpsemu {

struct RunStats {
  std::uint64_t epochs_emitted = 0;   ///< epochs formatted and handed to the outputs
  std::uint64_t epochs_late_skipped = 0;  ///< epochs skipped because their time had long passed
  std::uint64_t epochs_without_fix = 0;
  std::uint64_t pps_pulses = 0;               ///< leading edges driven
  std::uint64_t pps_pulses_late_skipped = 0;  ///< pulses not sent: their second had passed by over half the width
  /// Worst time from a leading edge's whole second to the return of the call that drove it.
  std::chrono::nanoseconds pps_worst_edge_delay{0};
};

/// What a Runner writes to when the caller (a test) provides it instead of config.outputs/pps.
struct RunnerIo {
  std::vector<std::unique_ptr<transport::Output>> outputs;
  std::unique_ptr<transport::PpsLine> pps;  ///< none: no PPS
};

class Runner {
 public:
  /// Opens the source and the outputs. Throws (std::exception with a clear message) when any of
  /// them cannot be set up: the caller exits with status 2.
  explicit Runner(const Config& config);
  /// Writes to `io` instead of opening config.outputs and config.pps (tests: recording fakes).
  Runner(const Config& config, RunnerIo io);
  ~Runner();

  /// Runs until the duration is reached or `stop` becomes true. Returns the process exit status.
  int run(const std::atomic<bool>& stop);

  [[nodiscard]] const RunStats& stats() const { return stats_; }
  [[nodiscard]] const std::vector<std::unique_ptr<transport::Output>>& outputs() const { return outputs_; }
  /// Epoch time minus wall time: 0, or the --start-time shift (whole seconds when PPS is on).
  [[nodiscard]] std::chrono::nanoseconds epoch_minus_wall() const { return sim_minus_wall_; }

 private:
  void init(std::optional<RunnerIo> io);
  void open_outputs();
  void open_pps();
  /// Drives every PPS edge due at or before `wall_deadline`, each at its time.
  void run_pps_until(UtcNs wall_deadline, const std::atomic<bool>& stop);
  void wait_until(UtcNs wall_deadline, const std::atomic<bool>& stop);
  void service_all();
  void log_summary() const;

  Config config_;
  EpochGrid grid_;
  LocalFrame frame_;
  std::int64_t first_index_ = 0;
  std::chrono::nanoseconds sim_minus_wall_{0};  ///< epoch time minus wall time (--start-time in real time)
  std::unique_ptr<sources::PoseSource> source_;
  std::unique_ptr<Receiver> receiver_;
  std::vector<std::unique_ptr<transport::Output>> outputs_;
  std::vector<pollfd> poll_fds_;  ///< reused by wait_until: no allocation per epoch
  std::unique_ptr<transport::PpsLine> pps_;  ///< after outputs_: a modem PPS line uses a serial output
  std::chrono::nanoseconds pps_width_{0};
  transport::PpsEdge next_edge_{};
  std::chrono::steady_clock::time_point last_pps_warning_{};
  RunStats stats_;
};

}  // namespace gpsemu
