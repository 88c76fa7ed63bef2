#include "emulator/pipeline/channel_set.hpp"

#include <algorithm>

namespace gpsemu {

ChannelSet::ChannelSet(const Timeline& timeline, std::optional<std::int64_t> epochs)
    : timeline_(timeline),
      end_(epochs ? timeline.grid.time_of(timeline.first_index + *epochs) : UtcNs::max()) {}

void ChannelSet::add(std::unique_ptr<Channel> channel) {
  receivers_.push_back({std::move(channel), ReceiverSchedule(timeline_.grid, timeline_.first_index), {}, false});
}

void ChannelSet::attach(const Sink& sink) {
  sink_ = &sink;
  for (std::size_t i = 0; i < receivers_.size(); ++i) {
    if (receivers_[i].channel->ubx_encoder()) receivers_[i].line = ubx_line_of(sink.outputs(i));
  }
}

bool ChannelSet::next_epoch(UtcNs& t) {
  // The earliest epoch of a receiver still sending.
  t = UtcNs::max();
  for (const Receiver& r : receivers_) {
    if (!r.channel->ended()) t = std::min(t, r.schedule.next());
  }
  if (t >= end_) return false;
  bool all_ended = true;
  for (Receiver& r : receivers_) {
    r.due = r.schedule.next() == t;
    if (r.due) r.schedule.advance();
    all_ended = r.channel->ended_at(t) && all_ended;
  }
  return !all_ended;
}

std::string_view ChannelSet::produce(std::size_t i, UtcNs t) {
  Receiver& r = receivers_[i];
  Channel& ch = *r.channel;
  // What a u-blox client asked for since the last epoch: its answer is already written.
  if (ch.ubx_encoder() && sink_) {
    const auto period = r.schedule.period();
    apply_ubx_effects(ch, sink_->outputs(i), r.schedule, r.line, t, sink_->who(i));
    if (r.schedule.period() != period && finest_changed_) finest_changed_(finest_period());
  }
  (void)ch.step(t);
  ++ch.stats().epochs_emitted;
  if (r.line.baud != 0) fit_epoch_to_line(ch, r.schedule.period(), r.line, sink_->who(i));
  return ch.bytes();
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
  if (extra_) {
    const std::size_t before = fds.size();
    extra_->fds(fds);
    owners.resize(owners.size() + (fds.size() - before), receivers_.size());
  }
}

void ChannelSet::service_inputs() {
  for (const Receiver& r : receivers_) r.channel->source()->service();
  if (extra_) extra_->service();
}

}  // namespace gpsemu
