#include "emulator/replay/replay_command.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "transport/posix/realtime.hpp"
#include "emulator/pipeline/serial_line_check.hpp"
#include "transport/output_spec.hpp"
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

EpochRange check_replay_options(const Config& config, const ReplayLog& log, const std::string& log_name) {
  if (config.clock.kind == ClockKind::scaled || config.clock.kind == ClockKind::lockstep) {
    throw std::invalid_argument(fmt::format("replay paces by the log's own times: use --speed K (or --fast), not "
                                            "--clock {}", to_string(config.clock)));
  }
  if (log.epochs.empty()) throw std::invalid_argument(fmt::format("NMEA log '{}' has no epochs", log_name));
  if (config.replay.loop && config.fast && !config.duration_s) {
    throw std::invalid_argument("--loop with --fast would never end: give --duration S (seconds of log time)");
  }
  try {
    return select_range(log, config.replay.from, config.replay.to);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("--{}", e.what()));
  }
}

Replayer::Replayer(const Config& config, ReplayLog log, std::string log_name,
                   std::vector<std::unique_ptr<transport::Output>> outputs, ClockIo& io)
    : config_(config), log_(std::move(log)), name_(std::move(log_name)), outputs_(std::move(outputs)), io_(io) {
  range_ = check_replay_options(config_, log_, name_);
}

int Replayer::run(const std::atomic<bool>& stop) {
  using namespace std::chrono;
  const auto& epochs = log_.epochs;
  const ReplayOptions& o = config_.replay;
  const nanoseconds base = epochs[range_.first].log_time;
  // One pass lasts from the first epoch to one nominal period after the last.
  const nanoseconds cycle = std::max(epochs[range_.last].log_time - base, nanoseconds::zero()) + log_.period;
  const auto latency = nanoseconds{std::llround(config_.latency_s * 1e9)};
  // A plain value, not an optional: GCC 12 at -O3 warns about the optional's storage.
  const nanoseconds duration =
      config_.duration_s ? nanoseconds{std::llround(*config_.duration_s * 1e9)} : nanoseconds::max();

  const UtcNs now = io_.now();
  UtcNs wall_0 = now;
  if (config_.start_time) {
    first_stamp_ = *config_.start_time;
  } else {
    // The log's first time shifted by whole seconds to the next such instant from now: a live
    // receiver's epochs keep their phase within the second.
    nanoseconds phase = base % seconds(1);
    if (phase < nanoseconds::zero()) phase += seconds(1);
    first_stamp_ = floor<seconds>(now) + phase;
    while (first_stamp_ < now + milliseconds(20)) first_stamp_ += seconds(1);
    if (o.retime && !config_.fast) wall_0 = first_stamp_ + latency;
  }

  spdlog::info("replay {}: epochs {}..{} of {} ({} to {}), nominal period {} s, speed {}{}{}{}", name_, range_.first,
               range_.last, epochs.size(), time_text(epochs[range_.first]), time_text(epochs[range_.last]),
               to_s(log_.period), o.speed, config_.fast ? ", no pacing (--fast)" : "", o.loop ? ", looping" : "",
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
      if (!config_.fast) io_.sleep_until(deadline, stop);
      if (stop.load()) break;
      std::string_view bytes = e.bytes;
      if (o.retime) {
        retimed = retime_epoch(e, first_stamp_ + v);
        bytes = retimed;
      }
      if (!config_.fast) {
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

std::vector<std::unique_ptr<transport::Output>> open_replay_outputs(const Config& config, const ReplayLog& log) {
  std::vector<transport::OutputSpec> specs;
  for (const std::string& text : config.outputs) specs.push_back(transport::parse_output_spec(text));
  // Epochs a second at this speed, for the serial line budget and queue.
  const double rate_hz = config.replay.speed / std::max(to_s(log.period), 1e-3);
  std::size_t widest = 0;
  for (const auto& e : log.epochs) widest = std::max(widest, e.bytes.size() + (config.replay.retime ? 8 * e.sentences.size() : 0));
  for (const auto& spec : specs) {
    if (spec.kind == transport::OutputKind::serial && !config.fast) check_serial_line_budget(spec, widest, rate_hz);
  }
  std::vector<std::unique_ptr<transport::Output>> outputs;
  for (const auto& spec : specs) {
    outputs.push_back(transport::make_output(spec, {.realtime = !config.fast, .rate_hz = rate_hz}));
  }
  if (config.tee) outputs.push_back(std::make_unique<transport::TeeOutput>(*config.tee, !config.fast));
  return outputs;
}

Subcommand add_replay_command(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand(
      "replay",
      "send a recorded NMEA log epoch by epoch, paced by its own time fields (binary, bad checksums and "
      "comments skipped): --speed, --loop, --from/--to, --retime, --fast, --output, --tee");
  sub->add_option("log", *path, "NMEA log (a receiver's raw stream, a gpsd log, a --tee file)")
      ->required()
      ->option_text("LOG");
  return {sub, [path](const Config& config, const std::atomic<bool>& stop) {
            ReplayLog log = read_replay_log(*path);
            (void)check_replay_options(config, log, *path);  // before any output is opened
            std::vector<std::unique_ptr<transport::Output>> outputs = open_replay_outputs(config, log);
            std::vector<transport::Output*> raw;
            for (const auto& out : outputs) raw.push_back(out.get());
            SystemClockIo io(
                [raw](std::vector<int>& fds) {
                  for (auto* out : raw) {
                    if (out->poll_fd() >= 0) fds.push_back(out->poll_fd());
                  }
                },
                [raw] {
                  for (auto* out : raw) out->service();
                });
            Replayer replayer(config, std::move(log), *path, std::move(outputs), io);
            // --realtime-priority, --lock-memory, --timer-slack: as for the emulator's loop.
            for (const std::string& line : posix::apply_realtime_settings(config.realtime)) spdlog::info("{}", line);
            return replayer.run(stop);
          }};
}

}  // namespace gpsemu::replay
