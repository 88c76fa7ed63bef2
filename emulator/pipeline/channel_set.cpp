#include "emulator/pipeline/channel_set.hpp"

#include "emulator/faults/tee_events.hpp"
#include "transport/tee_output.hpp"

#include <algorithm>

namespace gpsemu {

ChannelSet::ChannelSet(const Timeline& timeline, std::optional<std::int64_t> epochs)
    : timeline_(timeline),
      end_(epochs ? timeline.grid.time_of(timeline.first_index + *epochs) : UtcNs::max()),
      last_(epochs && *epochs > 0 ? timeline.grid.time_of(timeline.first_index + *epochs - 1) : UtcNs::max()) {}

void ChannelSet::add(std::unique_ptr<Channel> channel) {
  const ReceiverSchedule schedule(timeline_.grid, timeline_.first_index);
  receivers_.push_back({std::move(channel), schedule, schedule, {}, false});
}

void ChannelSet::attach(const Sink& sink) {
  sink_ = &sink;
  for (std::size_t i = 0; i < receivers_.size(); ++i) {
    if (receivers_[i].channel->protocol().has_tx_buffer()) receivers_[i].line = line_of(sink.outputs(i));
  }
}

bool ChannelSet::next_epoch(UtcNs& t) {
  // The earliest epoch of a receiver still sending.
  t = UtcNs::max();
  for (const Receiver& r : receivers_) {
    if (!r.channel->ended()) t = std::min(t, r.schedule.next());
  }
  if (t >= end_) {
    // No receiver has an epoch left in the run: wait idle for its last time on the grid, ports
    // open, unless an epoch was already there.
    const bool running = std::any_of(receivers_.begin(), receivers_.end(),
                                     [](const Receiver& r) { return !r.channel->ended(); });
    if (!running || last_ == UtcNs::max() || latest_ >= last_) return false;
    t = latest_ = last_;
    any_due_ = false;
    for (Receiver& r : receivers_) r.due = false;
    return true;
  }
  latest_ = t;
  any_due_ = true;
  bool all_ended = true;
  for (Receiver& r : receivers_) {
    r.due = r.schedule.next() == t;
    if (r.due) {
      r.previous = r.schedule;
      r.schedule.advance();
    }
    all_ended = r.channel->ended_at(t) && all_ended;
  }
  return !all_ended;
}

namespace {

/// The live events applied at this epoch, into the receiver's --tee file (a session to replay).
void record_events(const std::vector<faults::AppliedEvent>& events,
                   const std::vector<std::unique_ptr<transport::Output>>& outputs) {
  for (const faults::AppliedEvent& e : events) {
    const std::string line = faults::tee_event_line(e);
    for (const auto& out : outputs) out->note(line);  // the tee writes it; other outputs ignore it
  }
}

}  // namespace

std::string_view ChannelSet::produce(std::size_t i, UtcNs t) {
  Receiver& r = receivers_[i];
  Channel& ch = *r.channel;
  // What the protocol's client asked for since the last epoch: its answer is already written.
  if (sink_) {
    const auto period = r.schedule.period();
    apply_protocol_effects(ch, sink_->outputs(i), r.schedule, r.line, t, sink_->who(i));
    if (r.schedule.period() != period && finest_changed_) finest_changed_(finest_period());
  }
  const ReceiverEpoch epoch = ch.step(t);
  const nmea::Fix& fix = epoch.fix;
  ++ch.stats().epochs_emitted;
  if (observer_) observer_->epoch({i, t, ch, fix, sink_ ? &sink_->outputs(i) : nullptr, r.line});
  if (!ch.faults().applied_events().empty() && sink_) record_events(ch.faults().applied_events(), sink_->outputs(i));
  if (r.line.baud != 0) fit_epoch_to_line(ch, r.schedule.period(), r.line, sink_->who(i));
  return ch.bytes();
}

bool ChannelSet::reschedule_wanted() const {
  if (!sink_) return false;
  return std::any_of(receivers_.begin(), receivers_.end(),
                     [](const Receiver& r) { return r.channel->protocol().period_change_pending(); });
}

void ChannelSet::reschedule(UtcNs now) {
  const auto finest = finest_period();
  for (Receiver& r : receivers_) {
    if (r.due) r.schedule = r.previous;  // the epoch waited for comes again
    r.due = false;
  }
  for (std::size_t i = 0; i < receivers_.size(); ++i) {
    Receiver& r = receivers_[i];
    if (r.channel->protocol().period_change_pending()) {
      apply_protocol_effects(*r.channel, sink_->outputs(i), r.schedule, r.line, now, sink_->who(i));
    }
  }
  if (finest_period() != finest && finest_changed_) finest_changed_(finest_period());
}

std::chrono::nanoseconds ChannelSet::finest_period() const {
  auto finest = std::chrono::nanoseconds::max();
  for (const Receiver& r : receivers_) finest = std::min(finest, r.schedule.period());
  return finest;
}

void ChannelSet::list_inputs(std::vector<int>& fds, std::vector<std::size_t>& owners) const {
  for (std::size_t i = 0; i < receivers_.size(); ++i) {
    const int fd = receivers_[i].channel->source()->poll_fd();
    if (fd < 0) continue;
    fds.push_back(fd);
    owners.push_back(i);
  }
  extra_owner_.clear();
  for (std::size_t k = 0; k < extra_.size(); ++k) {
    const std::size_t before = fds.size();
    extra_[k]->fds(fds);
    for (std::size_t j = before; j < fds.size(); ++j) {
      owners.push_back(receivers_.size() + extra_owner_.size());
      extra_owner_.push_back(k);
    }
  }
}

void ChannelSet::service_inputs() {
  for (const Receiver& r : receivers_) r.channel->source()->service();
  for (LoopInput* input : extra_) input->service();
}

}  // namespace gpsemu
