#include "emulator/pipeline/runner.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "emulator/config/config.hpp"
#include "emulator/pipeline/channel_set.hpp"
#include "emulator/pipeline/epoch_loop.hpp"
#include "emulator/pipeline/protocol_effects.hpp"
#include "emulator/pipeline/rtk_receiver.hpp"
#include "emulator/ui/hub.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu {
namespace {

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

/// From this many receivers on, a second thread writes half of them (epoch_loop.cpp).
constexpr std::size_t kHelperWriterFrom = 8;

/// PPS marks real seconds: never with --fast.
bool with_pps(const LoopSettings& loop, const std::optional<RunnerIo>& io) {
  return loop.clock.kind != ClockKind::fast && (io ? io->pps != nullptr : loop.pps.spec.has_value());
}

RunSettings one_receiver(RunSettings settings) {
  if (settings.receivers.size() != 1) throw std::invalid_argument("a Runner given its outputs runs one receiver");
  return settings;
}

}  // namespace

Runner::Runner(const Config& config) : Runner(run_settings(config), std::nullopt) {}

Runner::Runner(const Config& config, RunnerIo io) : Runner(one_receiver(run_settings(config)), std::move(io)) {}

Runner::Runner(RunSettings settings, std::optional<RunnerIo> io)
    : loop_(std::move(settings.loop)),
      timeline_(choose_timeline(loop_.rate_hz, loop_.start_time, system_utc_now(), settings.receivers.size(),
                                with_pps(loop_, io))) {
  // The faults against the run's own epochs: without --start-time the first is known only now
  // (and with it whether an at_utc falls inside the run); with no protocol letting a client change a receiver's
  // rate every epoch is on the run's grid, and a fault after the last one would never start.
  {
    RunTimes run{timeline_.first_epoch(), !loop_.start_time, std::nullopt, std::nullopt};
    const bool on_the_grid = std::none_of(settings.receivers.begin(), settings.receivers.end(),
                                          [](const ReceiverSetup& r) { return r.channel.protocol && r.channel.protocol->client_may_change_period(); });
    if (loop_.epochs) run.run_s = static_cast<double>(*loop_.epochs) / loop_.rate_hz;
    if (loop_.epochs && *loop_.epochs > 0 && on_the_grid) run.last_epoch_s = static_cast<double>(*loop_.epochs - 1) / loop_.rate_hz;
    for (const ReceiverSetup& r : settings.receivers) check_fault_run_times(r.channel.faults.faults, run);
  }
  channels_ = std::make_unique<ChannelSet>(timeline_, loop_.epochs);
  for (const ReceiverSetup& r : settings.receivers) {
    auto ch = std::make_unique<Channel>(r.channel, timeline_.first_epoch());
    ch->set_source(r.make_source(ch->frame(), timeline_.first_epoch()));
    channels_->add(std::move(ch));
  }
  if (settings.watched) {
    hub_ = std::make_unique<ui::Hub>(*channels_, settings.status_every);
    channels_->set_observer(hub_.get());
    channels_->add_extra_input(hub_.get());
  }
  if (settings.control_path) {
    control_ = std::make_unique<ControlSocket>(*settings.control_path, *channels_, settings.control_idle_timeout);
    channels_->add_extra_input(control_.get());
    control_->set_status_extra([hub = hub_.get()](std::size_t i) { return hub->status_extra(i); });
    hub_->set_control_socket(control_.get());
  }
  if (io) {
    sink_.add(std::move(io->outputs));
    if (with_pps(loop_, io)) pps_line_ = std::move(io->pps);
  } else {
    for (const ReceiverSetup& r : settings.receivers) (void)sink_.open(r.outputs);
    if (with_pps(loop_, io)) pps_line_ = open_pps(loop_.pps, sink_);
  }
  for (std::size_t i = 0; i < sink_.receivers(); ++i) sink_.attach_client_input(i, &channels_->channel(i));
  channels_->attach(sink_);
  if (pps_line_) pps_ = std::make_unique<PpsTimeline>(*pps_line_, loop_.pps.width, timeline_.epoch_minus_wall);
  io_ = make_loop_io(sink_, *channels_);
  if (channels_->size() > 1 && loop_.clock.kind == ClockKind::lockstep) {
    std::vector<const sources::PoseSource*> sources;
    for (std::size_t i = 0; i < channels_->size(); ++i) sources.push_back(channels_->channel(i).source());
    fleet_time_ = std::make_unique<FleetSimTime>(std::move(sources));
  }
  clock_ = make_epoch_clock(loop_.clock, *io_, fleet_time_ ? *fleet_time_ : *channels_->channel(0).source(),
                            timeline_.first_epoch(), timeline_.first_wall() + loop_.latency, timeline_.grid.nominal_period(),
                            timeline_.epoch_minus_wall, loop_.latency,
                            // With PPS a step back moves the deadlines by whole seconds: epoch S still follows pulse S.
                            pps_ ? std::chrono::nanoseconds{std::chrono::seconds{1}} : std::chrono::nanoseconds{});
  // An epoch is late (skipped) by the finest period any receiver runs at, not only --rate's.
  channels_->on_finest_period([clock = clock_.get()](std::chrono::nanoseconds period) { clock->set_epoch_period(period); });
  // Everything that can fail is open: only now are the outputs' files truncated.
  sink_.commit();
  log_banner();
}

Runner::~Runner() = default;

const ReceiverStats& Runner::receiver_stats(std::size_t i) const {
  if (i >= channels_->size()) throw std::out_of_range("no such receiver");
  return channels_->channel(i).stats();
}

void Runner::log_banner() const {
  const std::size_t n = channels_->size();
  const bool fleet = n > 1;
  const double latency_ms = std::chrono::duration<double, std::milli>(loop_.latency).count();
  const UtcNs first_epoch = timeline_.first_epoch();
  if (fleet) {
    spdlog::info("{} receivers; {} Hz, latency {} ms; first epoch {}{}", n, loop_.rate_hz, latency_ms,
                 format_iso8601_utc(first_epoch),
                 n >= kHelperWriterFrom && loop_.clock.kind == ClockKind::realtime
                     ? "; two writer threads"
                     : "");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Channel& ch = channels_->channel(i);
    const ChannelSettings& s = ch.settings();
    const std::string who = sink_.who(i);
    if (fleet) {
      spdlog::info("{}source {}; noise {}, seed {}", who, ch.source()->describe(), noise::to_string(s.noise.model),
                   s.seed);
    } else {
      spdlog::info("source {}; noise {}; {} Hz, latency {} ms; first epoch {}", ch.source()->describe(),
                   noise::to_string(s.noise.model), loop_.rate_hz, latency_ms, format_iso8601_utc(first_epoch));
    }
    const Geometry& g = ch.receiver().geometry();
    // The widest epoch of what the receiver's protocol writes (a u-blox: its NMEA and binary messages).
    const std::size_t epoch_bytes = widest_epoch_bytes(ch);
    const std::string model = ch.protocol().receiver_name();  // empty: plain NMEA
    spdlog::info("{}receiver: {}GGA quality {} (noise x{}), {} of {} satellites used, HDOP {:.2f}; {} bytes an epoch at most{}",
                 who, model.empty() ? "" : model + ", ", static_cast<int>(s.receiver.quality),
                 noise_scale(s.receiver.quality), g.satellites_used, g.satellites_in_view, g.hdop, epoch_bytes,
                 model.empty() ? "" : " (" + ch.protocol().written() + ")");
    sink_.log_opened(i, ch.protocol().written());
  }
  if (pps_) pps_->log_opened();
  if (control_) spdlog::info("control socket {}: JSON lines, e.g. {{\"status\":true}}", control_->server().path());
}

int Runner::run(const std::atomic<bool>& stop) {
  if (!clock_->describe().empty()) spdlog::info("{}", clock_->describe());
  // In real time, PPS edges ride the epoch deadlines and a fleet computes ahead of them.
  const bool realtime = loop_.clock.kind == ClockKind::realtime;
  LoopOptions options;
  if (realtime && channels_->size() > 1) options.compute_ahead_within = loop_.latency;
  if (hub_) options.late_epochs = &hub_->late_epochs();
  if (pps_ && realtime) pps_->start(timeline_.first_wall());
  EpochLoop loop(*channels_, sink_, *clock_, options, realtime ? pps_.get() : nullptr);
  loop.run(stop);
  if (hub_) hub_->close();
  // Corrections already waiting when the run stops are read and counted, not left unaccounted.
  for (std::size_t i = 0; i < channels_->size(); ++i) channels_->channel(i).rtk().drain();
  stats_.epochs_emitted = loop.stats().epochs_emitted;
  stats_.epochs_late_skipped = loop.stats().epochs_late_skipped;
  stats_.clock_steps_back = loop.stats().clock_steps_back;
  stats_.epochs_without_fix = 0;
  for (std::size_t i = 0; i < channels_->size(); ++i) stats_.epochs_without_fix += channels_->channel(i).stats().epochs_without_fix;
  stats_.wakeups = io_->wakeups();
  stats_.waits_already_due = io_->waits_already_due();
  if (pps_) {
    stats_.pps_pulses = pps_->stats().pulses;
    stats_.pps_pulses_late_skipped = pps_->stats().pulses_late_skipped;
    stats_.pps_worst_edge_delay = pps_->stats().worst_edge_delay;
  }
  log_summary();
  return loop.exit_status();
}

void Runner::log_summary() const {
  spdlog::info("{} epochs emitted ({} without fix), {} late epochs skipped; {} wake-ups", stats_.epochs_emitted,
               stats_.epochs_without_fix, stats_.epochs_late_skipped, stats_.wakeups);
  if (stats_.clock_steps_back > 0) {
    spdlog::warn("the wall clock went back {} time(s); the epochs went on one period apart each time", stats_.clock_steps_back);
  }
  const std::size_t n = channels_->size();
  for (std::size_t i = 0; i < n; ++i) {
    const ReceiverStats& r = channels_->channel(i).stats();
    if (n > 1) spdlog::info("receiver {}: {} epochs ({} without fix)", i, r.epochs_emitted, r.epochs_without_fix);
    channels_->channel(i).faults().log_summary();
    if (r.epochs_silent != 0) {
      spdlog::info("{}{} epochs silent (nothing written; {} bytes of answers to the client withheld)", sink_.who(i),
                   r.epochs_silent, r.replies_withheld_bytes);
    }
    if (r.epochs_garbled != 0) {
      spdlog::info("{}{} epochs garbled ({} sentences/frames with a flipped bit, {} cut short)", sink_.who(i),
                   r.epochs_garbled, r.units_flipped, r.units_truncated);
    }
    if (r.epochs_delayed != 0) spdlog::info("{}{} epochs written late (latency)", sink_.who(i), r.epochs_delayed);
    sink_.log_summary(i);
    if (const std::string input = client_input_summary(channels_->channel(i)); !input.empty()) {
      spdlog::info("{}{}", sink_.who(i), input);
    }
    if (const std::string drops = tx_drops_summary(channels_->channel(i), channels_->line(i)); !drops.empty()) {
      spdlog::warn("{}{}", sink_.who(i), drops);
    }
    if (const std::string config = channels_->channel(i).protocol().configuration_summary(); !config.empty()) {
      spdlog::info("{}{}", sink_.who(i), config);
    }
    const Channel& ch = channels_->channel(i);
    const std::uint64_t port_bad_crc = ch.protocol().corrections_bad_crc();
    if (const std::string rtk = ch.rtk().summary(port_bad_crc); !rtk.empty()) spdlog::info("{}{}", sink_.who(i), rtk);
  }
  if (pps_) pps_->log_summary();
  if (control_) spdlog::info("{}", control_->summary());
  if (const std::uint64_t suppressed = log_lines_suppressed(); suppressed != 0) {
    spdlog::info("{} repeated log lines suppressed (at most a few a second of each kind are written)", suppressed);
  }
}

}  // namespace gpsemu
