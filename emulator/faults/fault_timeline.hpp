// The faults of one receiver applied to its epochs: the one point of the channel where they act
// (after the receiver model, before the encoders), so NMEA and UBX see the same fault. Given the
// epoch time it changes the fix coherently (quality, dimension, satellites and their C/N0, DOPs,
// position, GST sigmas) and a u-blox's RF state (MON-HW, MON-RF), and says whether the receiver
// writes at all. Logs each fault's start and end with its epoch time and counts its epochs.
// Deterministic: the same faults, truth and fixes give the same result.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "emulator/common/log_limit.hpp"
#include "emulator/faults/fault.hpp"
#include "emulator/model/enu.hpp"
#include "emulator/model/epoch.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/time.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::faults {

/// One receiver's faults, as the channel takes them.
struct FaultPlan {
  std::vector<Fault> faults;  ///< those that apply to this receiver, in scenario order
  std::string who;            ///< log prefix ("" or "receiver 2: ")
};

/// What the faults of an epoch leave to the channel.
struct EpochEffect {
  bool silent = false;  ///< write nothing this epoch
  /// A reset starts: the receiver reboots at this epoch (a u-blox reloads its configuration from
  /// its layers) and starts cold, no fix for this long from now (seconds).
  std::optional<double> reboot_cold_start_s;
  double garble_rate = 0.0;  ///< garble: fraction of the epoch's sentences and frames to corrupt
  double delay_ms = 0.0;     ///< latency: write the epoch's bytes this much late ...
  double jitter_ms = 0.0;    ///< ... plus a draw in [0, jitter_ms)
};

/// A live event (the control socket) as it was applied: the epoch it took effect at and the
/// request, normalised, so a session can be written to the --tee file and replayed
/// (`--scenario` takes a --tee file's "# fault" lines: tee_events.hpp).
struct AppliedEvent {
  UtcNs epoch;           ///< the epoch it took effect at
  double since_s = 0.0;  ///< the same, seconds after the first epoch
  std::string request;   ///< one JSON object: {"fault":...} or {"clear":...}, with "receiver"
};

class FaultTimeline {
 public:
  FaultTimeline(FaultPlan plan, UtcNs first_epoch);

  /// Applies the faults active at `t` to `epoch` as the model and RTK built it: its fix (for
  /// `truth_m` in `frame`; no truth: the position is not touched) and its RF front end (clean
  /// unless a fault acts on it this epoch). Call once per epoch with non-decreasing `t`.
  EpochEffect apply(UtcNs t, ReceiverEpoch& epoch, const std::optional<Enu>& truth_m, const LocalFrame& frame);

  struct Entry {
    Fault fault;
    std::uint64_t epochs = 0;  ///< epochs it was active (its fade out included)
    bool active = false;
    bool ended = false;
    bool cleared = false;                ///< a clear ended it: it does not start again
    std::optional<double> cleared_s{};   ///< the epoch the clear applied at (s after the first epoch)
    std::optional<double> entered_s{};   ///< where: when the truth entered the area (the start of this visit)
    std::optional<double> fading_from_s{};  ///< ramp_out_s: when it ended and began to fade
    double strength = 0.0;               ///< its strength at the last epoch it was active
  };
  [[nodiscard]] const std::vector<Entry>& entries() const { return entries_; }
  [[nodiscard]] bool empty() const { return entries_.empty(); }

  /// A live fault (the control socket): it starts at the next epoch, its `at_s` ignored, and lasts
  /// its duration from there (none: until cleared).
  /// `request`: the request as the --tee file records it once applied (applied_events()).
  void add_live(Fault fault, std::string request = {}) {
    pending_.push_back(std::move(fault));
    pending_requests_.push_back(std::move(request));
  }
  /// Ends at the next epoch every fault of `kind` that is active or waiting (live or from the
  /// scenario); returns how many. `request` as for add_live (recorded once, with the first kind).
  int clear(FaultKind kind, std::string request = {});
  /// The live faults accepted since the last epoch, to start at the next one.
  [[nodiscard]] const std::vector<Fault>& pending() const { return pending_; }
  /// Whether a clear of `kind` waits for the next epoch.
  [[nodiscard]] bool clear_pending(FaultKind kind) const {
    for (const auto& [k, request] : pending_clears_) {
      if (k == kind) return true;
    }
    return false;
  }
  /// The live events applied at the last epoch (empty most epochs).
  [[nodiscard]] const std::vector<AppliedEvent>& applied_events() const { return applied_; }

  /// The last epoch, as the control socket's status reports it.
  struct LastEpoch {
    std::uint64_t epochs = 0;  ///< epochs applied so far
    double since_s = 0.0;      ///< the last epoch's time after the first epoch (seconds)
    nmea::FixQuality quality = nmea::FixQuality::none;
    int satellites_used = 0;
    bool silent = false;
  };
  [[nodiscard]] const LastEpoch& last_epoch() const { return last_epoch_; }
  /// One line per fault: what it was (a cleared one: until its clear) and how many epochs it covered.
  [[nodiscard]] std::vector<std::string> summary_lines() const;
  /// Logs summary_lines().
  void log_summary() const;

 private:
  /// Takes the live faults and clears asked for since the last epoch (time `t`, `since_s`).
  void take_pending(UtcNs t, double since_s, const nmea::Fix& fix);
  /// Whether entry `e` is active at `since_s` (its trigger: time, UTC, or the truth in an area).
  bool active_now(Entry& e, double since_s, const std::optional<Enu>& truth_m, const LocalFrame& frame) const;

  std::vector<Entry> entries_;
  std::vector<Fault> pending_;             ///< live faults to start at the next epoch
  std::vector<std::string> pending_requests_;  ///< their requests, for applied_
  std::vector<std::pair<FaultKind, std::string>> pending_clears_;  ///< kinds to end at the next epoch
  std::vector<AppliedEvent> applied_;
  LastEpoch last_epoch_;
  std::string who_;
  LogLimit applied_log_{5};  ///< "control: applied" lines: a few a second (a flood of requests)
  UtcNs first_epoch_;
  bool keeps_last_ = false;            ///< a freeze is still to come: keep the last fix
  std::optional<nmea::Fix> last_;      ///< the last epoch's fix as written
  std::optional<nmea::Fix> frozen_;    ///< the fix a freeze repeats
};

/// Moves `fix`'s position by `offset` in `frame` (jump, wrong).
void offset_position(nmea::Fix& fix, const Enu& offset, const LocalFrame& frame);
/// Scales `fix`'s position error about `truth_m` by `k` (degrade, jam, fix-quality).
void scale_error(nmea::Fix& fix, const Enu& truth_m, double k, const LocalFrame& frame);
/// No fix: what a receiver reports when it lost its solution (satellites still listed, none used).
void drop_fix(nmea::Fix& fix);

}  // namespace gpsemu::faults
