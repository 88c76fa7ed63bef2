#include "emulator/pipeline/runner.hpp"

#include <time.h>

#include <cerrno>
#include <cmath>
#include <algorithm>
#include <limits>

#include <spdlog/spdlog.h>

#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/epoch_text.hpp"
#include "emulator/config/receiver_config.hpp"
#include "emulator/pipeline/serial_line_check.hpp"
#include "transport/gpio_pps.hpp"
#include "transport/modem_pps.hpp"
#include "transport/posix/wall_clock.hpp"
#include "transport/serial_output.hpp"
#include "transport/tee_output.hpp"

namespace gpsemu {
namespace {

UtcNs wall_now() { return posix::wall_clock_now(); }

/// Many receivers with --clock lockstep: the simulators' common present is the slowest one's.
/// Only its sim_time() is used (by the lockstep clock).
class FleetSimTime final : public sources::PoseSource {
 public:
  explicit FleetSimTime(std::vector<const sources::PoseSource*> sources) : sources_(std::move(sources)) {}
  std::optional<sources::Truth> truth_at(UtcNs /*t*/) override { return std::nullopt; }
  std::string describe() const override { return "the slowest simulator's time"; }
  std::optional<UtcNs> sim_time() const override {
    std::optional<UtcNs> slowest;
    for (const auto* source : sources_) {
      const auto t = source->sim_time();
      if (!t) return std::nullopt;  // a simulator that has not started holds every epoch
      if (!slowest || *t < *slowest) slowest = t;
    }
    return slowest;
  }

 private:
  std::vector<const sources::PoseSource*> sources_;
};

/// From this many receivers on, a second thread writes half of them at the deadline.
constexpr std::size_t kHelperWriterFrom = 8;
/// Shortest lead for computing many receivers' epochs ahead of the deadline.
constexpr std::chrono::microseconds kMinComputeLead{300};

}  // namespace

Runner::Runner(const Config& config) : config_(config), grid_(config.timeline.rate_hz) { init(std::nullopt); }

Runner::Runner(const Config& config, RunnerIo io) : config_(config), grid_(config.timeline.rate_hz) {
  if (static_cast<int>(config.receivers.size()) != 1) throw std::invalid_argument("a Runner given its outputs runs one receiver");
  init(std::move(io));
}

void Runner::init(std::optional<RunnerIo> io) {
  const Config& config = config_;
  const UtcNs now = wall_now();
  // The first epoch: the next grid epoch after now, or after --start-time. With --start-time in
  // real time, epoch times are shifted by a whole number of epochs from the wall clock, so the
  // sub-second phase of every epoch still matches the wall clock; with PPS, by a whole number of
  // seconds, so the second an epoch is stamped with is the second its pulse marks.
  // Many receivers take a while to open (256 sockets or ptys, their banners): the first epoch is
  // one far enough ahead that it is not already late when the loop starts (2 ms a receiver).
  const auto start_up = std::chrono::milliseconds(1) + std::chrono::milliseconds(2) * (static_cast<int>(config.receivers.size()) - 1);
  const std::int64_t wall_index = grid_.index_at_or_after(now + start_up);
  first_index_ = config.timeline.start_time ? grid_.index_at_or_after(*config.timeline.start_time) : wall_index;
  const bool with_pps = !config.timeline.fast() && (io ? io->pps != nullptr : config.timeline.pps.has_value());
  if (config.timeline.start_time && with_pps) {
    const UtcNs first = grid_.time_of(first_index_);
    const auto phase = first - std::chrono::floor<std::chrono::seconds>(first);
    const UtcNs first_wall =
        std::chrono::ceil<std::chrono::seconds>(now + start_up - phase) + phase;
    sim_minus_wall_ = first - first_wall;
  } else {
    sim_minus_wall_ = grid_.time_of(first_index_) - grid_.time_of(wall_index);
  }
  const UtcNs first_epoch = grid_.time_of(first_index_);

  for (const ReceiverSettings& rc : config.receivers) channels_.push_back(std::make_unique<Channel>(rc));
  for (auto& ch : channels_) {
    ch->source = make_receiver_source(ch->config, config.timeline, ch->frame, first_epoch);
    ch->receiver = std::make_unique<Receiver>(ch->frame, receiver_options(ch->config),
                                              noise::make_noise_model(ch->config.noise, ch->config.seed), first_epoch);
    ch->text.reserve(1024);
  }
  if (io) {
    channels_.front()->outputs = std::move(io->outputs);
    if (with_pps) pps_ = std::move(io->pps);
  } else {
    for (auto& ch : channels_) open_outputs(*ch);
    if (with_pps) open_pps();
  }
  // The clock polls every output's and source's descriptor and services those with input.
  clock_io_ = std::make_unique<SystemClockIo>(
      [this](std::vector<int>& fds) {
        pollables_.clear();
        for (auto& ch : channels_) {
          for (auto& out : ch->outputs) {
            if (out->poll_fd() < 0) continue;
            fds.push_back(out->poll_fd());
            pollables_.push_back({.output = out.get()});
          }
          if (ch->source->poll_fd() < 0) continue;
          fds.push_back(ch->source->poll_fd());
          pollables_.push_back({.source = ch->source.get()});
        }
      },
      SystemClockIo::ReadyServicer([this](std::size_t k) {
        const Pollable& p = pollables_[k];
        if (p.output) p.output->service();
        if (p.source) p.source->service();
      }));
  if (channels_.size() > 1 && config.timeline.clock.kind == ClockKind::lockstep) {
    std::vector<const sources::PoseSource*> sources;
    for (const auto& ch : channels_) sources.push_back(ch->source.get());
    fleet_time_ = std::make_unique<FleetSimTime>(std::move(sources));
  }
  pps_width_ = std::chrono::nanoseconds{std::llround(config.timeline.pps_width_s * 1e9)};
  if (channels_.size() > 1) {
    spdlog::info("{} receivers; {} Hz, latency {} ms; first epoch {}{}", channels_.size(), config.timeline.rate_hz,
                 config.timeline.latency_s * 1000.0, format_iso8601_utc(first_epoch),
                 channels_.size() >= kHelperWriterFrom && !config.timeline.fast() && config.timeline.clock.kind == ClockKind::realtime
                     ? "; two writer threads"
                     : "");
  }
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    const Channel& ch = *channels_[i];
    const std::string who = channels_.size() > 1 ? fmt::format("receiver {}: ", i) : std::string();
    if (channels_.size() > 1) {
      spdlog::info("{}source {}; noise {}, seed {}", who, ch.source->describe(), noise::to_string(ch.config.noise.model),
                   ch.config.seed);
    } else {
      spdlog::info("source {}; noise {}; {} Hz, latency {} ms; first epoch {}", ch.source->describe(),
                   noise::to_string(ch.config.noise.model), config.timeline.rate_hz, config.timeline.latency_s * 1000.0,
                   format_iso8601_utc(first_epoch));
    }
    const Geometry& g = ch.receiver->geometry();
    spdlog::info("{}receiver: GGA quality {} (noise x{}), {} of {} satellites used, HDOP {:.2f}; {} bytes an epoch at most",
                 who, static_cast<int>(ch.config.model.quality), noise_scale(ch.config.model.quality),
                 g.satellites_used, g.satellites_in_view, g.hdop,
                 nmea::line_budget(ch.config.format, g.satellites_in_view, g.satellites_used, config.timeline.rate_hz)
                     .bytes_per_epoch);
    for (const auto& out : ch.outputs) spdlog::info("{}NMEA on {}", who, out->describe());
  }
  if (pps_) {
    spdlog::info("PPS on {}: leading edge at each whole UTC second, {} ms wide, {}", pps_->describe(),
                 config.timeline.pps_width_s * 1000.0,
                 pps_->polarity() == transport::PpsPolarity::active_high ? "high during the pulse" : "low during the pulse");
  }
}

void Runner::open_outputs(Channel& ch) {
  const ReceiverSettings& config = ch.config;
  const std::vector<transport::OutputSpec>& specs = config.outputs;
  // Refuse a serial line that cannot carry the epochs before opening anything.
  std::optional<std::size_t> epoch_bytes;
  for (const auto& spec : specs) {
    if (spec.kind != transport::OutputKind::serial) continue;
    if (!epoch_bytes) epoch_bytes = worst_case_epoch_bytes(config.format);
    check_serial_line_budget(spec, *epoch_bytes, config_.timeline.rate_hz);
  }
  for (const auto& spec : specs) {
    ch.outputs.push_back(transport::make_output(
        spec, transport::OutputOptions{.realtime = !config_.timeline.fast(), .rate_hz = config_.timeline.rate_hz}));
  }
  if (config.tee) ch.outputs.push_back(std::make_unique<transport::TeeOutput>(*config.tee, !config_.timeline.fast()));
}

void Runner::open_pps() {
  const transport::PpsSpec& spec = *config_.timeline.pps;
  const auto polarity =
      config_.timeline.pps_active_low ? transport::PpsPolarity::active_low : transport::PpsPolarity::active_high;
  if (spec.kind == transport::PpsSpec::Kind::gpio) {
    pps_ = std::make_unique<transport::GpioPps>(spec.chip, spec.line, polarity);
    return;
  }
  for (const auto& ch : channels_) {
    for (const auto& out : ch->outputs) {
      if (auto* serial = dynamic_cast<transport::SerialOutput*>(out.get())) {
        pps_ = std::make_unique<transport::ModemPps>(*serial, spec.modem_line, polarity);
        return;
      }
    }
  }
  throw std::runtime_error(fmt::format(
      "--pps {}: drives a modem line of the serial output, but there is no serial output: add --output "
      "serial:DEVICE[@BAUD] (a pty output has no modem lines; with one, use --pps gpio:CHIP:LINE)",
      transport::to_string(spec)));
}

Runner::~Runner() = default;

int Runner::run(const std::atomic<bool>& stop) {
  const auto latency = std::chrono::nanoseconds{std::llround(config_.timeline.latency_s * 1e9)};
  const std::int64_t count = config_.timeline.duration_s ? std::llround(*config_.timeline.duration_s * config_.timeline.rate_hz)
                                                : std::numeric_limits<std::int64_t>::max();
  const bool fleet = channels_.size() > 1;
  if (channels_.size() >= kHelperWriterFrom && !config_.timeline.fast() && config_.timeline.clock.kind == ClockKind::realtime && !helper_) {
    // Made here, by the thread that runs the loop, after main() applied --realtime-priority and
    // --timer-slack to it: the helper inherits them.
    helper_ = std::make_unique<HelperWriter>(
        [this](std::size_t first, std::size_t from, std::size_t to) { write_range(first, from, to); });
  }
  if (pps_) {
    // The first pulse: the first whole second at or after the first epoch (in wall time).
    const UtcNs first_wall = grid_.time_of(first_index_) - sim_minus_wall_;
    next_edge_ = {std::chrono::ceil<std::chrono::seconds>(first_wall), true};
  }
  // --clock scaled:K / lockstep pace the epochs instead of the real-time code below (clock.hpp).
  const auto clock = make_epoch_clock(config_.timeline.clock, *clock_io_, fleet_time_ ? *fleet_time_ : *channels_.front()->source,
                                      grid_.time_of(first_index_), grid_.time_of(first_index_) - sim_minus_wall_ + latency,
                                      grid_.nominal_period());
  if (clock) spdlog::info("{}", clock->describe());
  for (std::int64_t k = 0; !stop.load() && k < count; ++k) {
    const UtcNs t = grid_.time_of(first_index_ + k);
    bool all_ended = true;
    for (auto& ch : channels_) {
      ch->ended = ch->ended || ch->source->ended_at(t);
      all_ended = all_ended && ch->ended;
    }
    if (all_ended) break;
    if (clock) {
      const EpochWait wait = clock->wait_for(t, stop);
      if (wait == EpochWait::stopped) break;
      if (wait == EpochWait::skip) {
        ++stats_.epochs_late_skipped;
        continue;
      }
    } else if (!config_.timeline.fast()) {
      const UtcNs deadline = t - sim_minus_wall_ + latency;
      // Every PPS edge due before the epoch's bytes goes first (a leading edge at the same
      // instant too: the NMEA of second S follows pulse S).
      if (pps_ && !fleet) run_pps_until(deadline, stop);  // a fleet drives them in run_fleet_epoch()
      if (stop.load()) break;
      // An epoch whose time has long passed (the process was stopped or starved) is skipped, not
      // sent late in a burst: a receiver never reports the past.
      if (wall_now() - deadline > grid_.nominal_period()) {
        ++stats_.epochs_late_skipped;
        spdlog::warn("epoch {} skipped: {} ms late", format_iso8601_utc(t),
                     std::chrono::duration_cast<std::chrono::milliseconds>(wall_now() - deadline).count());
        continue;
      }
      if (fleet) {
        if (!run_fleet_epoch(k, t, deadline, stop)) break;
        ++stats_.epochs_emitted;
        continue;
      }
      wait_until(deadline, stop);
      if (stop.load()) break;
    }
    for (auto& ch : channels_) {
      if (ch->ended) continue;
      compute(*ch, t, false);
      write(*ch);
    }
    ++stats_.epochs_emitted;
    if (config_.timeline.fast() && (k & 0x3ff) == 0) service_all();
  }
  if (helper_) helper_->wait_done();
  if (pps_ && pps_->pulse_on()) {
    // End the last pulse at its time (at once when stopped), never leave the line in a pulse.
    if (!stop.load()) wait_until(next_edge_.time, stop);
    pps_->set(false);
  }
  for (auto& ch : channels_) {
    for (auto& out : ch->outputs) out->flush();
  }
  stats_.wakeups = clock_io_->wakeups();
  log_summary();
  return 0;
}

void Runner::compute(Channel& ch, UtcNs t, bool prepare_outputs) {
  ch.source->service();
  const nmea::Fix fix = ch.receiver->fix_at(t, ch.source->truth_at(t));
  if (!fix.has_fix()) {
    ++ch.stats.epochs_without_fix;
    ++stats_.epochs_without_fix;
  }
  format_epoch(fix, ch.config.format, ch.text);
  if (prepare_outputs) {
    for (auto& out : ch.outputs) out->prepare_epoch();
  }
}

void Runner::write(Channel& ch) {
  for (auto& out : ch.outputs) (void)out->write_epoch(ch.text);
  ++ch.stats.epochs_emitted;
}

void Runner::write_range(std::size_t first, std::size_t from, std::size_t to) {
  const std::size_t n = channels_.size();
  for (std::size_t pos = from; pos < to; ++pos) {
    Channel& ch = *channels_[(first + pos) % n];
    if (!ch.ended) write(ch);
  }
}

bool Runner::run_fleet_epoch(std::int64_t k, UtcNs t, UtcNs deadline, const std::atomic<bool>& stop) {
  // Compute ahead by twice the recent cost, within the latency: never before the epoch's own time
  // (a receiver's fix for t is computed after t), so with no latency it is done at the deadline.
  const auto lead = std::clamp(2 * compute_cost_ + kMinComputeLead, std::chrono::nanoseconds{0}, deadline - (t - sim_minus_wall_));
  const UtcNs compute_at = deadline - lead;
  if (pps_) run_pps_until(compute_at, stop);
  wait_until(compute_at, stop);
  if (stop.load()) return false;
  const auto begin = std::chrono::steady_clock::now();
  for (auto& ch : channels_) {
    if (!ch->ended) compute(*ch, t, true);
  }
  const auto cost = std::chrono::steady_clock::now() - begin;
  // A decaying maximum: one slow epoch raises the lead at once, which then shrinks by 1% an epoch.
  compute_cost_ = std::max(std::chrono::nanoseconds{cost}, compute_cost_ * 99 / 100);
  const std::size_t n = channels_.size();
  const std::size_t first = static_cast<std::size_t>(k % static_cast<std::int64_t>(n));
  const std::size_t mine = helper_ ? n / 2 : n;
  if (helper_) helper_->post(deadline, first, mine, n);
  if (pps_) run_pps_until(deadline, stop);
  wait_until(deadline, stop);
  // Stopped while waiting: the helper still writes its part at the deadline; write ours too, so
  // an epoch is never half sent.
  write_range(first, 0, mine);
  if (helper_) helper_->wait_done();
  return !stop.load();
}

void Runner::run_pps_until(UtcNs wall_deadline, const std::atomic<bool>& stop) {
  while (!stop.load() && next_edge_.time <= wall_deadline) {
    wait_until(next_edge_.time, stop);
    if (stop.load()) return;
    const transport::PpsEdge edge = next_edge_;
    next_edge_ = transport::next_pps_edge(edge, pps_width_);
    const auto late = wall_now() - edge.time;
    if (edge.leading && late > pps_width_ / 2) {
      // A pulse that late would mark the wrong instant: skip it (and its trailing edge).
      ++stats_.pps_pulses_late_skipped;
      next_edge_ = transport::next_pps_edge(next_edge_, pps_width_);
      const auto now = std::chrono::steady_clock::now();
      if (now - last_pps_warning_ >= std::chrono::seconds(1)) {
        spdlog::warn("PPS pulse of {} skipped: {} ms late", format_iso8601_utc(edge.time + sim_minus_wall_),
                     std::chrono::duration_cast<std::chrono::milliseconds>(late).count());
        last_pps_warning_ = now;
      }
      continue;
    }
    if (pps_->set(edge.leading) && edge.leading) {
      ++stats_.pps_pulses;
      stats_.pps_worst_edge_delay = std::max(stats_.pps_worst_edge_delay, wall_now() - edge.time);
    }
  }
}

void Runner::service_all() {
  for (auto& ch : channels_) {
    for (auto& out : ch->outputs) out->service();
    ch->source->service();
  }
}

void Runner::log_summary() const {
  spdlog::info("{} epochs emitted ({} without fix), {} late epochs skipped; {} wake-ups", stats_.epochs_emitted,
               stats_.epochs_without_fix, stats_.epochs_late_skipped, stats_.wakeups);
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    const Channel& ch = *channels_[i];
    std::string who;
    if (channels_.size() > 1) {
      who = fmt::format("receiver {}: ", i);
      spdlog::info("receiver {}: {} epochs ({} without fix)", i, ch.stats.epochs_emitted, ch.stats.epochs_without_fix);
    }
    for (const auto& out : ch.outputs) {
      const auto& s = out->stats();
      spdlog::info("{}{}: {} epochs written ({} bytes), {} dropped, {} failed", who, out->describe(), s.epochs_written,
                   s.bytes_written, s.epochs_dropped, s.epochs_failed);
    }
  }
  if (pps_) {
    spdlog::info("PPS {}: {} pulses, {} skipped late, {} edges failed; worst leading edge {:.3f} ms after its second",
                 pps_->describe(), stats_.pps_pulses, stats_.pps_pulses_late_skipped, pps_->stats().failures,
                 std::chrono::duration<double, std::milli>(stats_.pps_worst_edge_delay).count());
  }
}

}  // namespace gpsemu
