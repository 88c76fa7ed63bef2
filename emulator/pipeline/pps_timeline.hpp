// The PPS line on the epoch timeline: its leading edge at each whole UTC second S (wall clock), its
// trailing edge at S + width, driven by the epoch loop before each epoch's bytes (the NMEA stamped
// S follows pulse S). A pulse whose second has passed by more than half the width is skipped: it
// would mark the wrong instant.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "emulator/model/time.hpp"
#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/sink.hpp"
#include "transport/pps.hpp"

namespace gpsemu {

/// --pps and its options (pipeline/run_settings.hpp builds them from a Config).
struct PpsSettings {
  std::optional<transport::PpsSpec> spec;  ///< gpio:CHIP:LINE | modem:RTS | modem:DTR; none: no PPS
  std::chrono::nanoseconds width{100'000'000};
  bool active_low = false;
};

/// Opens the line `settings` names (spec given): a GPIO line, or a modem line of the sink's serial output.
/// Throws std::runtime_error when a modem line has no serial output to drive.
[[nodiscard]] std::unique_ptr<transport::PpsLine> open_pps(const PpsSettings& settings, const Sink& sink);

struct PpsStats {
  std::uint64_t pulses = 0;               ///< leading edges driven
  std::uint64_t pulses_late_skipped = 0;  ///< pulses not sent: their second had passed by over half the width
  /// Worst time from a leading edge's whole second to the return of the call that drove it.
  std::chrono::nanoseconds worst_edge_delay{0};
};

class PpsTimeline {
 public:
  /// `epoch_minus_wall` only names a skipped pulse's second in the log.
  PpsTimeline(transport::PpsLine& line, std::chrono::nanoseconds width, std::chrono::nanoseconds epoch_minus_wall)
      : line_(line), width_(width), shift_(epoch_minus_wall) {}

  /// The first pulse: the first whole second at or after the first epoch's wall time.
  void start(UtcNs first_wall);
  /// Drives every edge due at or before `wall_deadline`, each at its time (waiting through `io`).
  /// Returns early, before an edge, when `woken` (if given) returns true after input was serviced.
  void run_until(UtcNs wall_deadline, ClockIo& io, const std::atomic<bool>& stop,
                 const std::function<bool()>* woken = nullptr);
  /// Ends the last pulse at its time (at once when stopped): the line is never left in a pulse.
  void finish(ClockIo& io, const std::atomic<bool>& stop);

  [[nodiscard]] const PpsStats& stats() const { return stats_; }
  [[nodiscard]] const transport::PpsLine& line() const { return line_; }
  /// The start-up line and the summary line.
  void log_opened() const;
  void log_summary() const;

 private:
  transport::PpsLine& line_;
  std::chrono::nanoseconds width_;
  std::chrono::nanoseconds shift_;
  transport::PpsEdge next_edge_{};
  LogLimit skip_log_{1};  ///< "PPS pulse ... skipped" lines: at most one a second
  PpsStats stats_;
};

}  // namespace gpsemu
