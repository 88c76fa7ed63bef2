#include "emulator/sources/fix_transitions.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

namespace gpsemu::sources {
namespace {

double seconds(std::chrono::nanoseconds d) { return std::chrono::duration<double>(d).count(); }

}  // namespace

void FixTransitions::note(bool has_truth, UtcNs t, const PoseHistory& history, std::string_view owner) {
  const State now = has_truth ? State::fresh : (state_ == State::waiting ? State::waiting : State::stale);
  if (now == state_) return;
  if (now == State::stale && !history.empty() && history.newest().time > t) {
    // The history starts after this epoch (a sender restarted and its first poses lie ahead, or
    // a late epoch): no truth yet, not a silence of negative length.
    spdlog::warn("pose input: no {} yet at epoch {} (the {} held begin {:.2f} s after it): reporting no fix until then",
                 one_, format_iso8601_utc(t), many_, seconds(history.oldest().time - t));
  } else if (now == State::stale) {
    spdlog::warn("pose input: no {} for {:.2f} s (timeout {} s): reporting no fix until {} resume", one_,
                 history.empty() ? 0.0 : seconds(t - history.newest().time), seconds(history.options().timeout),
                 many_);
  } else if (state_ == State::waiting) {
    spdlog::info("pose input: fix from {} at epoch {}", owner, format_iso8601_utc(t));
  } else {
    spdlog::info("pose input: {} resumed from {}: fix again at epoch {}", many_, owner, format_iso8601_utc(t));
  }
  state_ = now;
}

}  // namespace gpsemu::sources
