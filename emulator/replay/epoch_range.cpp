#include "emulator/replay/epoch_range.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::replay {
namespace {

using std::chrono::nanoseconds;
constexpr nanoseconds kDay = std::chrono::hours(24);

/// Positive remainder of a by b.
nanoseconds mod(nanoseconds a, nanoseconds b) {
  const nanoseconds r = a % b;
  return r < nanoseconds::zero() ? r + b : r;
}

/// A time of day as a point on the log's timeline: its first occurrence at or after `ref`.
nanoseconds on_timeline(nanoseconds ref, const LogPosition& p) {
  return ref + mod(std::get<nanoseconds>(p.value) - mod(ref, kDay), kDay);
}

std::string time_of_day_text(nanoseconds log_time) { return to_string(LogPosition{mod(log_time, kDay)}); }

std::optional<std::int64_t> index_of(const std::optional<LogPosition>& p) {
  if (!p || p->is_time_of_day()) return std::nullopt;
  return std::get<std::int64_t>(p->value);
}

}  // namespace

RangeCursor::RangeCursor(std::optional<LogPosition> from, std::optional<LogPosition> to, nanoseconds first_log_time)
    : from_(std::move(from)), to_(std::move(to)), first_log_time_(first_log_time) {
  for (const auto& [key, p] : {std::pair{"from", index_of(from_)}, std::pair{"to", index_of(to_)}}) {
    if (p && *p < 0) throw std::invalid_argument(fmt::format("{}: epoch {} does not exist (the first is 0)", key, *p));
  }
  if (index_of(from_) && index_of(to_) && *index_of(to_) < *index_of(from_)) {
    throw std::invalid_argument(fmt::format("to: epoch {} comes before the first one selected (epoch {})",
                                            *index_of(to_), *index_of(from_)));
  }
}

RangeCursor::Place RangeCursor::place(std::uint64_t index, const LogEpoch& epoch) {
  if (last_index_ == index) return last_place_;
  last_index_ = index;
  if (!first_) {
    const auto from_index = index_of(from_);
    const bool before = from_ && (from_index ? static_cast<std::int64_t>(index) < *from_index
                                             : epoch.log_time < on_timeline(first_log_time_, *from_));
    if (before) return last_place_ = Place::before;
    first_ = index;
    // Where --to's time of day is looked for from.
    const nanoseconds from_time =
        !from_ ? first_log_time_ : (from_index ? epoch.log_time : on_timeline(first_log_time_, *from_));
    if (to_ && to_->is_time_of_day()) {
      to_time_ = on_timeline(from_time, *to_);
      if (epoch.log_time > *to_time_) {
        throw std::invalid_argument(fmt::format("to: {}: no epoch from {} up to it", to_string(*to_),
                                                from_ ? to_string(*from_) : "the start"));
      }
    }
    if (const auto to_index = index_of(to_); to_index && *to_index < static_cast<std::int64_t>(index)) {
      throw std::invalid_argument(fmt::format("to: epoch {} comes before the first one selected (epoch {})", *to_index,
                                              index));
    }
    return last_place_ = Place::in;
  }
  if (last_place_ == Place::after) return Place::after;
  const auto to_index = index_of(to_);
  if ((to_time_ && epoch.log_time > *to_time_) || (to_index && static_cast<std::int64_t>(index) > *to_index)) {
    return last_place_ = Place::after;
  }
  return last_place_ = Place::in;
}

void RangeCursor::at_end(std::uint64_t epochs, nanoseconds last_log_time) const {
  if (!first_ && from_) {
    if (const auto i = index_of(from_)) {
      throw std::invalid_argument(fmt::format("from: epoch {} is past the end: the log has {} epochs (0..{})", *i,
                                              epochs, epochs - 1));
    }
    throw std::invalid_argument(fmt::format("from: {}: no epoch at or after it in the log (its times run from {} to {})",
                                            to_string(*from_), time_of_day_text(first_log_time_),
                                            time_of_day_text(last_log_time)));
  }
  if (to_index_beyond(epochs - 1)) {
    throw std::invalid_argument(fmt::format("to: epoch {} is past the end: the log has {} epochs (0..{})",
                                            *index_of(to_), epochs, epochs - 1));
  }
}

bool RangeCursor::to_index_beyond(std::uint64_t last_index) const {
  const auto i = index_of(to_);
  return i && static_cast<std::uint64_t>(*i) > last_index;
}

void RangeCursor::restart() {
  first_.reset();
  to_time_.reset();
  last_index_.reset();
  last_place_ = Place::before;
}

}  // namespace gpsemu::replay
