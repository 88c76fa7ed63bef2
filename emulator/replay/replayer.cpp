#include "emulator/replay/replayer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "emulator/config/validate.hpp"
#include "emulator/pipeline/epoch_loop.hpp"

namespace gpsemu::replay {
namespace {

using std::chrono::nanoseconds;

double to_s(nanoseconds d) { return std::chrono::duration<double>(d).count(); }
double ms(nanoseconds d) { return std::chrono::duration<double, std::milli>(d).count(); }

std::string time_text(const LogEpoch& e) {
  return e.time_of_day ? to_string(LogPosition{*e.time_of_day}) : "(no time)";
}

/// The log's epochs of the range, pass after pass. An epoch's time on the loop's timeline is its
/// log time since the range's first epoch (plus a cycle a pass), from UtcNs{0}.
class RecordedEpochs final : public EpochProducer {
 public:
  RecordedEpochs(const ReplayLog& log, const EpochRange& range, const ReplayPacing& settings, UtcNs first_stamp,
                 ReplayStats& stats)
      : log_(log), range_(range), retime_(settings.options.retime), loop_(settings.options.loop),
        duration_(settings.duration.value_or(nanoseconds::max())), first_stamp_(first_stamp), stats_(stats),
        base_(log.epochs[range.first].log_time),
        // One pass lasts from the first epoch to one nominal period after the last.
        cycle_(std::max(log.epochs[range.last].log_time - base_, nanoseconds::zero()) + log.period),
        next_(range.first) {}

  bool next_epoch(UtcNs& t) override {
    if (next_ > range_.last || stats_.passes == 0) {
      if (stats_.passes > 0 && !loop_) return false;
      ++stats_.passes;
      next_ = range_.first;
    }
    current_ = next_++;
    const nanoseconds v = static_cast<std::int64_t>(stats_.passes - 1) * cycle_ + (log_.epochs[current_].log_time - base_);
    t = UtcNs{v};
    return v < duration_;
  }

  std::string_view produce(std::size_t /*receiver*/, UtcNs t) override {
    const LogEpoch& e = log_.epochs[current_];
    std::string_view bytes = e.bytes;
    if (retime_) {
      retimed_ = retime_epoch(e, first_stamp_ + t.time_since_epoch());
      bytes = retimed_;
    }
    ++stats_.epochs_sent;
    stats_.sentences_sent += e.sentences.size();
    stats_.bytes_sent += bytes.size();
    return bytes;
  }

 private:
  const ReplayLog& log_;
  EpochRange range_;
  bool retime_, loop_;
  nanoseconds duration_;
  UtcNs first_stamp_;
  ReplayStats& stats_;
  nanoseconds base_, cycle_;
  std::size_t next_, current_ = 0;
  std::string retimed_;
};

}  // namespace

EpochRange check_replay_options(const TimelineSettings& timeline, const ReplaySettings& replay, const ReplayLog& log,
                                const std::string& log_name) {
  check_replay_settings(timeline, replay, !log.epochs.empty(), log_name);
  try {
    return select_range(log, replay.from, replay.to);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("--{}", e.what()));
  }
}

std::vector<std::unique_ptr<transport::Output>> open_replay_outputs(const ReceiverSettings& receiver,
                                                                   const TimelineSettings& timeline,
                                                                   const ReplaySettings& replay, const ReplayLog& log) {
  OutputSettings out = receiver_setup(receiver, timeline).outputs;
  // Epochs a second at this speed, for the serial line budget and queue.
  out.rate_hz = replay.speed / std::max(to_s(log.period), 1e-3);
  out.widest_epoch_bytes = nullptr;
  if (out.realtime) {
    out.widest_epoch_bytes = [&log, retime = replay.retime] {
      std::size_t widest = 0;
      for (const auto& e : log.epochs) widest = std::max(widest, e.bytes.size() + (retime ? 8 * e.sentences.size() : 0));
      return widest;
    };
  }
  return open_outputs(out);
}

Replayer::Replayer(const TimelineSettings& timeline, const ReplaySettings& replay, ReplayLog log,
                   std::string log_name, std::vector<std::unique_ptr<transport::Output>> outputs, ClockIo& io)
    : Replayer(timeline, replay, std::move(log), std::move(log_name), std::move(outputs)) {
  io_ = &io;
}

Replayer::Replayer(const TimelineSettings& timeline, const ReplaySettings& replay, ReplayLog log,
                   std::string log_name, std::vector<std::unique_ptr<transport::Output>> outputs)
    : settings_(replay_pacing(timeline, replay)), log_(std::move(log)), name_(std::move(log_name)) {
  range_ = check_replay_options(timeline, replay, log_, name_);
  sink_.add(std::move(outputs));
  sink_.commit();  // every output is open: only now are their files truncated
}

Replayer::~Replayer() = default;

int Replayer::run(const std::atomic<bool>& stop) {
  using namespace std::chrono;
  const ReplayOptions& o = settings_.options;
  const nanoseconds base = log_.epochs[range_.first].log_time;
  stats_ = {};
  const UtcNs now = io_ ? io_->now() : system_utc_now();
  UtcNs wall_0 = now;
  if (settings_.start_time) {
    first_stamp_ = *settings_.start_time;
  } else {
    // The log's first time shifted by whole seconds to the next such instant from now: a live
    // receiver's epochs keep their phase within the second.
    nanoseconds phase = base % seconds(1);
    if (phase < nanoseconds::zero()) phase += seconds(1);
    first_stamp_ = floor<seconds>(now) + phase;
    while (first_stamp_ < now + milliseconds(20)) first_stamp_ += seconds(1);
    if (o.retime && !settings_.fast) wall_0 = first_stamp_ + settings_.latency;
  }
  RecordedEpochs epochs(log_, range_, settings_, first_stamp_, stats_);
  std::unique_ptr<SystemClockIo> system_io;
  if (!io_) system_io = make_loop_io(sink_, epochs);
  ClockIo& io = io_ ? *io_ : *system_io;

  spdlog::info("replay {}: epochs {}..{} of {} ({} to {}), nominal period {} s, speed {}{}{}{}", name_, range_.first,
               range_.last, log_.epochs.size(), time_text(log_.epochs[range_.first]),
               time_text(log_.epochs[range_.last]), to_s(log_.period), o.speed,
               settings_.fast ? ", no pacing (--fast)" : "", o.loop ? ", looping" : "",
               o.retime ? fmt::format(", retimed from {}", format_iso8601_utc(first_stamp_)) : "");
  sink_.log_opened(0);

  // The log's timeline from UtcNs{0}, at `speed` times real time from wall_0; never skipped.
  std::unique_ptr<EpochClock> clock;
  if (settings_.fast) {
    clock = std::make_unique<FastClock>();
  } else {
    clock = std::make_unique<ScaledClock>(io, o.speed, UtcNs{}, wall_0, log_.period, /*skip_late=*/false);
  }
  LoopOptions options;
  options.measure_send_delay = true;
  EpochLoop loop(epochs, sink_, *clock, options);
  loop.run(stop);
  stats_.worst_delay = loop.stats().worst_delay;
  stats_.total_delay = loop.stats().total_delay;
  log_summary();
  if (loop.stats().outputs_gone) {
    spdlog::error("every output is gone (the reader of the pipe closed it): stopped");
    return 1;
  }
  return 0;
}

void Replayer::log_summary() const {
  const LogCounts& n = log_.counts;
  const auto& s = n.stream;
  spdlog::info("replay {}: {} epochs sent ({} sentences, {} bytes) in {} pass{}; worst send delay {:.3f} ms, mean "
               "{:.3f} ms", name_, stats_.epochs_sent, stats_.sentences_sent, stats_.bytes_sent, stats_.passes,
               stats_.passes == 1 ? "" : "es", ms(stats_.worst_delay),
               stats_.epochs_sent ? ms(stats_.total_delay) / static_cast<double>(stats_.epochs_sent) : 0.0);
  spdlog::info("replay {}: skipped {} bad checksums, {} malformed sentences, {} binary/garbage bytes, {} comment "
               "lines; log: {} epochs ({} without a time, {} bad time fields), {} gaps (longest {:.3f} s), {} steps "
               "back, {} midnight rollovers, {} oversized epochs skipped ({} sentences)", name_, s.bad_checksum, s.malformed,
               s.garbage_bytes, s.comment_lines, log_.epochs.size(), n.untimed_epochs, n.bad_time_fields, n.gaps,
               to_s(n.longest_gap), n.steps_back, n.rollovers, n.oversized_epochs, n.oversized_sentences);
  sink_.log_summary(0);
}

}  // namespace gpsemu::replay
