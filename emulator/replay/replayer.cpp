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
#include "nmea/line_budget.hpp"

namespace gpsemu::replay {
namespace {

using std::chrono::nanoseconds;

double to_s(nanoseconds d) { return std::chrono::duration<double>(d).count(); }
double ms(nanoseconds d) { return std::chrono::duration<double, std::milli>(d).count(); }

std::string time_text(const LogEpoch& e) {
  return e.time_of_day ? to_string(LogPosition{*e.time_of_day}) : "(no time)";
}

/// The log's epochs of the range, pass after pass, read as they are sent. An epoch's time on the
/// loop's timeline is its log time since the range's first epoch (plus a cycle a pass), from UtcNs{0}.
class RecordedEpochs final : public EpochProducer {
 public:
  RecordedEpochs(LogStream& log, RangeCursor& range, const ReplayPacing& settings, UtcNs first_stamp,
                 nanoseconds base, std::optional<std::size_t> line_budget_bytes, ReplayStats& stats)
      : log_(log), range_(range), retime_(settings.options.retime), loop_(settings.options.loop),
        duration_(settings.duration.value_or(nanoseconds::max())), first_stamp_(first_stamp),
        line_budget_bytes_(line_budget_bytes), stats_(stats), base_(base) {}

  bool next_epoch(UtcNs& t) override {
    if (stats_.passes == 0) stats_.passes = 1;  // the log is at the range's first epoch
    bool sent_this_pass = stats_.epochs_sent > sent_before_pass_;
    for (;;) {
      const LogEpoch* e = log_.peek();
      const auto place = e ? range_.place(log_.position(), *e) : RangeCursor::Place::after;
      if (place == RangeCursor::Place::in) break;
      if (place == RangeCursor::Place::before) {
        (void)log_.pop();
        continue;
      }
      if (!e && !stats_.to_past_the_end && range_.to_index_beyond(log_.position() - 1)) {
        stats_.to_past_the_end = true;
        spdlog::warn("--to: the log ends at epoch {}, before {}: sent up to its last epoch", log_.position() - 1,
                     to_ ? to_string(*to_) : "");
      }
      // The end of a pass: one nominal period after its last epoch, the next one starts.
      if (!loop_ || !sent_this_pass) return false;
      cycle_ = std::max(last_log_time_ - base_, nanoseconds::zero()) + log_.period();
      log_.rewind();
      range_.restart();
      ++stats_.passes;
      sent_before_pass_ = stats_.epochs_sent;
      sent_this_pass = false;
    }
    (void)log_.pop(&current_);
    last_log_time_ = current_.log_time;
    const nanoseconds v = static_cast<std::int64_t>(stats_.passes - 1) * cycle_ + (current_.log_time - base_);
    t = UtcNs{v};
    return v < duration_;
  }

  std::string_view produce(std::size_t /*receiver*/, UtcNs t) override {
    std::string_view bytes = current_.bytes;
    if (retime_) {
      retimed_ = retime_epoch(current_, first_stamp_ + t.time_since_epoch());
      bytes = retimed_;
    }
    ++stats_.epochs_sent;
    stats_.sentences_sent += current_.sentences.size();
    stats_.bytes_sent += bytes.size();
    if (line_budget_bytes_ && bytes.size() > *line_budget_bytes_ && stats_.epochs_over_line_budget++ == 0) {
      spdlog::warn("epoch at {} is {} bytes: wider than the {} bytes the serial line carries at this rate (counted in "
                   "the summary)", time_text(current_), bytes.size(), *line_budget_bytes_);
    }
    return bytes;
  }

  /// --to, for the message when the log ends before its index.
  void set_to(std::optional<LogPosition> to) { to_ = std::move(to); }

 private:
  LogStream& log_;
  RangeCursor& range_;
  bool retime_, loop_;
  nanoseconds duration_;
  UtcNs first_stamp_;
  std::optional<std::size_t> line_budget_bytes_;
  ReplayStats& stats_;
  nanoseconds base_;
  nanoseconds cycle_{0};
  nanoseconds last_log_time_{0};
  std::uint64_t sent_before_pass_ = 0;
  std::optional<LogPosition> to_;
  LogEpoch current_;
  std::string retimed_;
};

/// The options' messages name the option: "from: ..." becomes "--from: ...".
[[noreturn]] void rethrow_naming_option(const std::invalid_argument& e) {
  throw std::invalid_argument(fmt::format("--{}", e.what()));
}

}  // namespace

RangeCursor check_replay_options(const TimelineSettings& timeline, const ReplaySettings& replay, LogStream& log) {
  check_replay_settings(timeline, replay, !log.window().empty(), log.name());
  if (replay.loop && !log.can_rewind()) {
    throw std::invalid_argument(fmt::format("--loop: NMEA log '{}' is not a regular file: a pipe can be read only once",
                                            log.name()));
  }
  try {
    RangeCursor range(replay.from, replay.to, log.first_log_time());
    nanoseconds last_log_time = log.first_log_time();
    for (;;) {
      const LogEpoch* e = log.peek();
      if (!e) {
        range.at_end(log.position(), last_log_time);
        break;
      }
      if (range.place(log.position(), *e) != RangeCursor::Place::before) break;
      last_log_time = e->log_time;
      (void)log.pop();
    }
    // --to's index, when the window reaches the end of the log.
    if (log.ended() && range.to_index_beyond(log.position() + log.window().size() - 1)) {
      range.at_end(log.position() + log.window().size(), log.window().back().log_time);
    }
    return range;
  } catch (const std::invalid_argument& e) {
    rethrow_naming_option(e);
  }
}

namespace {

/// The replay's epochs a second, for the serial line budget and queue.
double replay_rate_hz(const ReplaySettings& replay, const LogStream& log) {
  return replay.speed / std::max(to_s(log.period()), 1e-3);
}

}  // namespace

std::vector<std::unique_ptr<transport::Output>> open_replay_outputs(const ReceiverSettings& receiver,
                                                                   const TimelineSettings& timeline,
                                                                   const ReplaySettings& replay, const LogStream& log) {
  OutputSettings out = receiver_setup(receiver, timeline).outputs;
  out.rate_hz = replay_rate_hz(replay, log);
  out.widest_epoch_bytes = nullptr;
  if (out.realtime) {
    out.widest_epoch_bytes = [&log, retime = replay.retime] {
      std::size_t widest = 0;
      for (const auto& e : log.window()) widest = std::max(widest, e.bytes.size() + (retime ? 8 * e.sentences.size() : 0));
      return widest;
    };
  }
  return open_outputs(out);
}

std::optional<std::size_t> replay_line_budget_bytes(const ReceiverSettings& receiver, const TimelineSettings& timeline,
                                                    const ReplaySettings& replay, const LogStream& log) {
  const OutputSettings out = receiver_setup(receiver, timeline).outputs;
  if (!out.realtime) return std::nullopt;
  std::optional<std::size_t> budget;
  for (const auto& spec : out.outputs) {
    if (spec.kind != transport::OutputKind::serial) continue;
    const int baud = spec.baud_bps != 0 ? spec.baud_bps : nmea::kDefaultBaud;
    const auto bytes = static_cast<std::size_t>(nmea::line_bytes_per_second(baud) * nmea::kLineBudgetMargin /
                                                replay_rate_hz(replay, log));
    budget = std::min(budget.value_or(bytes), bytes);
  }
  return budget;
}

Replayer::Replayer(const TimelineSettings& timeline, const ReplaySettings& replay, std::unique_ptr<LogStream>&& log,
                   RangeCursor range, std::vector<std::unique_ptr<transport::Output>> outputs, ClockIo* io,
                   std::optional<std::size_t> line_budget_bytes)
    : settings_(replay_pacing(timeline, replay)), log_(std::move(log)), range_(std::move(range)), io_(io),
      line_budget_bytes_(line_budget_bytes) {
  sink_.add(std::move(outputs));
  sink_.commit();  // every output is open: only now are their files truncated
}

Replayer::Replayer(const TimelineSettings& timeline, const ReplaySettings& replay, std::unique_ptr<LogStream> log,
                   std::vector<std::unique_ptr<transport::Output>> outputs, ClockIo& io)
    : Replayer(timeline, replay, std::move(log), check_replay_options(timeline, replay, *log), std::move(outputs),
               &io) {}

Replayer::~Replayer() = default;

int Replayer::run(const std::atomic<bool>& stop) {
  using namespace std::chrono;
  const ReplayOptions& o = settings_.options;
  const LogEpoch* first = log_->peek();
  if (first == nullptr) return 0;  // check_replay_options() refused an empty range
  const nanoseconds base = first->log_time;
  const std::string first_text = fmt::format("epoch {} ({})", log_->position(), time_text(*first));
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
  RecordedEpochs epochs(*log_, range_, settings_, first_stamp_, base, line_budget_bytes_, stats_);
  epochs.set_to(o.to);
  std::unique_ptr<SystemClockIo> system_io;
  if (!io_) system_io = make_loop_io(sink_, epochs);
  ClockIo& io = io_ ? *io_ : *system_io;

  spdlog::info("replay {}: from {}{}, nominal period {} s (median of the first {} spacings), speed {}{}{}{}",
               log_->name(), first_text, o.to ? " to " + to_string(*o.to) : "", to_s(log_->period()),
               log_->period_spacings(), o.speed, settings_.fast ? ", no pacing (--fast)" : "",
               o.loop ? ", looping" : "",
               o.retime ? fmt::format(", retimed from {}", format_iso8601_utc(first_stamp_)) : "");
  sink_.log_opened(0);

  // The log's timeline from UtcNs{0}, at `speed` times real time from wall_0; never skipped.
  std::unique_ptr<EpochClock> clock;
  if (settings_.fast) {
    clock = std::make_unique<FastClock>();
  } else {
    clock = std::make_unique<ScaledClock>(io, o.speed, UtcNs{}, wall_0, log_->period(), /*skip_late=*/false);
  }
  LoopOptions options;
  options.measure_send_delay = true;
  EpochLoop loop(epochs, sink_, *clock, options);
  loop.run(stop);
  stats_.worst_delay = loop.stats().worst_delay;
  stats_.total_delay = loop.stats().total_delay;
  log_summary();
  return loop.exit_status();
}

void Replayer::log_summary() const {
  const LogCounts& n = log_->counts();
  const auto& s = n.stream;
  const std::string& name = log_->name();
  spdlog::info("replay {}: {} epochs sent ({} sentences, {} bytes) in {} pass{}; worst send delay {:.3f} ms, mean "
               "{:.3f} ms", name, stats_.epochs_sent, stats_.sentences_sent, stats_.bytes_sent, stats_.passes,
               stats_.passes == 1 ? "" : "es", ms(stats_.worst_delay),
               stats_.epochs_sent ? ms(stats_.total_delay) / static_cast<double>(stats_.epochs_sent) : 0.0);
  // The log's counts are final once it was read to its end; else they cover what was read.
  spdlog::info("replay {}: skipped {} bad checksums, {} malformed sentences, {} binary/garbage bytes, {} comment "
               "lines; log{}: {} epochs ({} without a time, {} bad time fields), {} gaps (longest {:.3f} s), {} steps "
               "back, {} midnight rollovers, {} oversized epochs skipped ({} sentences)", name, s.bad_checksum,
               s.malformed, s.garbage_bytes, s.comment_lines,
               log_->ended() ? "" : fmt::format(" (its first {} bytes, read so far)", log_->bytes_read()),
               log_->epochs_read(), n.untimed_epochs, n.bad_time_fields, n.gaps, to_s(n.longest_gap), n.steps_back,
               n.rollovers, n.oversized_epochs, n.oversized_sentences);
  if (line_budget_bytes_) {
    spdlog::log(stats_.epochs_over_line_budget > 0 ? spdlog::level::warn : spdlog::level::info,
                "replay {}: {} epochs wider than the {} bytes the slowest serial line carries at this rate", name,
                stats_.epochs_over_line_budget, *line_budget_bytes_);
  }
  sink_.log_summary(0);
}

}  // namespace gpsemu::replay
