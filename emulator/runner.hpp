// The main loop: for each epoch on the UTC grid, sample the pose source, run the receiver model,
// format the sentences and hand them to every output at epoch time + latency (or as fast as
// possible with --fast). Absolute deadlines, so nothing drifts.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "emulator/config.hpp"
#include "emulator/geo.hpp"
#include "emulator/receiver.hpp"
#include "emulator/sources/pose_source.hpp"
#include "emulator/time.hpp"
#include "transport/output.hpp"

namespace gpsemu {

struct RunStats {
  std::uint64_t epochs_emitted = 0;   ///< epochs formatted and handed to the outputs
  std::uint64_t epochs_late_skipped = 0;  ///< epochs skipped because their time had long passed
  std::uint64_t epochs_without_fix = 0;
};

class Runner {
 public:
  /// Opens the source and the outputs. Throws (std::exception with a clear message) when any of
  /// them cannot be set up: the caller exits with status 2.
  explicit Runner(const Config& config);
  ~Runner();

  /// Runs until the duration is reached or `stop` becomes true. Returns the process exit status.
  int run(const std::atomic<bool>& stop);

  [[nodiscard]] const RunStats& stats() const { return stats_; }
  [[nodiscard]] const std::vector<std::unique_ptr<transport::Output>>& outputs() const { return outputs_; }

 private:
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
  RunStats stats_;
};

}  // namespace gpsemu
