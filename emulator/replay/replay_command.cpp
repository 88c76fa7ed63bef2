#include "emulator/replay/replay_command.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "emulator/config/validate.hpp"
#include "emulator/pipeline/serial_line_check.hpp"
#include "transport/tee_output.hpp"

namespace gpsemu::replay {
namespace {

using std::chrono::nanoseconds;

double to_s(nanoseconds d) { return std::chrono::duration<double>(d).count(); }
double ms(nanoseconds d) { return std::chrono::duration<double, std::milli>(d).count(); }

nanoseconds scaled(nanoseconds d, double speed) {
  return nanoseconds{std::llround(static_cast<double>(d.count()) / speed)};
}

std::string time_text(const LogEpoch& e) {
  return e.time_of_day ? to_string(LogPosition{*e.time_of_day}) : "(no time)";
}

}  // namespace

EpochRange check_replay_options(const TimelineSettings& timeline, const ReplaySettings& replay,
                                const ReplayLog& log, const std::string& log_name) {
  check_replay_settings(timeline, replay, !log.epochs.empty(), log_name);
  try {
    return select_range(log, replay.from, replay.to);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("--{}", e.what()));
  }
}

Replayer::Replayer(const TimelineSettings& timeline, const ReplaySettings& replay, ReplayLog log, std::string log_name,
                   std::vector<std::unique_ptr<transport::Output>> outputs, ClockIo& io)
    : timeline_(timeline), options_(replay), log_(std::move(log)), name_(std::move(log_name)),
      outputs_(std::move(outputs)), io_(io) {
  range_ = check_replay_options(timeline_, options_, log_, name_);
}

int Replayer::run(const std::atomic<bool>& stop) {
  using namespace std::chrono;
  const auto& epochs = log_.epochs;
  const ReplayOptions& o = options_;
  const nanoseconds base = epochs[range_.first].log_time;
  // One pass lasts from the first epoch to one nominal period after the last.
  const nanoseconds cycle = std::max(epochs[range_.last].log_time - base, nanoseconds::zero()) + log_.period;
  const auto latency = nanoseconds{std::llround(timeline_.latency_s * 1e9)};
  // A plain value, not an optional: GCC 12 at -O3 warns about the optional's storage.
  const nanoseconds duration =
      timeline_.duration_s ? nanoseconds{std::llround(*timeline_.duration_s * 1e9)} : nanoseconds::max();

  const UtcNs now = io_.now();
  UtcNs wall_0 = now;
  if (timeline_.start_time) {
    first_stamp_ = *timeline_.start_time;
  } else {
    // The log's first time shifted by whole seconds to the next such instant from now: a live
    // receiver's epochs keep their phase within the second.
    nanoseconds phase = base % seconds(1);
    if (phase < nanoseconds::zero()) phase += seconds(1);
    first_stamp_ = floor<seconds>(now) + phase;
    while (first_stamp_ < now + milliseconds(20)) first_stamp_ += seconds(1);
    if (o.retime && !timeline_.fast()) wall_0 = first_stamp_ + latency;
  }

  spdlog::info("replay {}: epochs {}..{} of {} ({} to {}), nominal period {} s, speed {}{}{}{}", name_, range_.first,
               range_.last, epochs.size(), time_text(epochs[range_.first]), time_text(epochs[range_.last]),
               to_s(log_.period), o.speed, timeline_.fast() ? ", no pacing (--fast)" : "", o.loop ? ", looping" : "",
               o.retime ? fmt::format(", retimed from {}", format_iso8601_utc(first_stamp_)) : "");
  for (const auto& out : outputs_) spdlog::info("NMEA on {}", out->describe());

  std::string retimed;
  bool done = false;
  UtcNs latest_deadline = wall_0;
  for (std::uint64_t pass = 0; !done && !stop.load(); ++pass) {
    ++stats_.passes;
    for (std::size_t i = range_.first; i <= range_.last; ++i) {
      const LogEpoch& e = epochs[i];
      const nanoseconds v = static_cast<std::int64_t>(pass) * cycle + (e.log_time - base);
      if (v >= duration) {
        done = true;
        break;
      }
      const UtcNs deadline = wall_0 + scaled(v, o.speed);
      if (!timeline_.fast()) io_.sleep_until(deadline, stop);
      if (stop.load()) break;
      std::string_view bytes = e.bytes;
      if (o.retime) {
        retimed = retime_epoch(e, first_stamp_ + v);
        bytes = retimed;
      }
      if (!timeline_.fast()) {
        // Against the deadline it could be met at: an epoch whose time went back is due with
        // the previous one, not at its own (past) deadline.
        latest_deadline = std::max(latest_deadline, deadline);
        const nanoseconds delay = std::max(io_.now() - latest_deadline, nanoseconds::zero());
        stats_.worst_delay = std::max(stats_.worst_delay, delay);
        stats_.total_delay += delay;
      } else if ((stats_.epochs_sent & 0x3ff) == 0) {
        for (auto& out : outputs_) out->service();
      }
      for (auto& out : outputs_) (void)out->write_epoch(bytes);
      ++stats_.epochs_sent;
      stats_.sentences_sent += e.sentences.size();
      stats_.bytes_sent += bytes.size();
    }
    if (!o.loop) break;
  }
  for (auto& out : outputs_) out->flush();
  log_summary();
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
               "back, {} midnight rollovers", name_, s.bad_checksum, s.malformed, s.garbage_bytes, s.comment_lines,
               log_.epochs.size(), n.untimed_epochs, n.bad_time_fields, n.gaps, to_s(n.longest_gap),
               n.steps_back, n.rollovers);
  for (const auto& out : outputs_) {
    const auto& o = out->stats();
    spdlog::info("{}: {} epochs written ({} bytes), {} dropped, {} failed", out->describe(), o.epochs_written,
                 o.bytes_written, o.epochs_dropped, o.epochs_failed);
  }
}

std::vector<std::unique_ptr<transport::Output>> open_replay_outputs(const ReceiverSettings& receiver,
                                                                   const TimelineSettings& timeline,
                                                                   const ReplaySettings& replay, const ReplayLog& log) {
  const std::vector<transport::OutputSpec>& specs = receiver.outputs;
  // Epochs a second at this speed, for the serial line budget and queue.
  const double rate_hz = replay.speed / std::max(to_s(log.period), 1e-3);
  std::size_t widest = 0;
  for (const auto& e : log.epochs) widest = std::max(widest, e.bytes.size() + (replay.retime ? 8 * e.sentences.size() : 0));
  for (const auto& spec : specs) {
    if (spec.kind == transport::OutputKind::serial && !timeline.fast()) check_serial_line_budget(spec, widest, rate_hz);
  }
  std::vector<std::unique_ptr<transport::Output>> outputs;
  for (const auto& spec : specs) {
    outputs.push_back(transport::make_output(spec, {.realtime = !timeline.fast(), .rate_hz = rate_hz}));
  }
  if (receiver.tee) outputs.push_back(std::make_unique<transport::TeeOutput>(*receiver.tee, !timeline.fast()));
  return outputs;
}

}  // namespace gpsemu::replay
