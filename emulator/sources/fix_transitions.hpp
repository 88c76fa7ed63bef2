// What a socket-fed source (JSON poses, MAVLink states) logs as its truth comes and goes: the first
// fix, "no pose for X s" once when the newest pose gets older than the timeout, and the fix again
// when poses resume. One line per transition, whichever source; the truth itself comes from the
// pose history (pose_history.hpp).
#pragma once

#include <string>
#include <string_view>

#include "emulator/model/time.hpp"
#include "emulator/sources/pose_history.hpp"

namespace gpsemu::sources {

class FixTransitions {
 public:
  /// `one` and `many` name what the source receives: "pose" / "poses", "MAVLink state" / "MAVLink states".
  FixTransitions(std::string one, std::string many) : one_(std::move(one)), many_(std::move(many)) {}

  /// Notes whether the history had a truth at epoch `t` (from `owner`) and logs a change.
  void note(bool has_truth, UtcNs t, const PoseHistory& history, std::string_view owner);

 private:
  enum class State { waiting, fresh, stale };
  std::string one_, many_;
  State state_ = State::waiting;
};

}  // namespace gpsemu::sources
