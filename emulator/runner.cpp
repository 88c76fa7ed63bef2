#include "emulator/runner.hpp"

#include <poll.h>
#include <time.h>

#include <cerrno>
#include <cmath>
#include <limits>

#include <spdlog/spdlog.h>

#include "emulator/clock.hpp"
#include "emulator/epoch_text.hpp"
#include "emulator/receiver_config.hpp"
#include "emulator/serial_line_check.hpp"
#include "emulator/sources/make_source.hpp"
#include "transport/gpio_pps.hpp"
#include "transport/modem_pps.hpp"
#include "transport/output_spec.hpp"
#include "transport/serial_output.hpp"
#include "transport/tee_output.hpp"

namespace gpsemu {
namespace {

UtcNs wall_now() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return UtcNs{std::chrono::nanoseconds{static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec}};
}

}  // namespace

Runner::Runner(const Config& config) : config_(config), grid_(config.rate_hz), frame_(config.origin) {
  init(std::nullopt);
}

Runner::Runner(const Config& config, RunnerIo io)
    : config_(config), grid_(config.rate_hz), frame_(config.origin) {
  init(std::move(io));
}

void Runner::init(std::optional<RunnerIo> io) {
  const Config& config = config_;
  const UtcNs now = wall_now();
  // The first epoch: the next grid epoch after now, or after --start-time. With --start-time in
  // real time, epoch times are shifted by a whole number of epochs from the wall clock, so the
  // sub-second phase of every epoch still matches the wall clock; with PPS, by a whole number of
  // seconds, so the second an epoch is stamped with is the second its pulse marks.
  const std::int64_t wall_index = grid_.index_at_or_after(now + std::chrono::milliseconds(1));
  first_index_ = config.start_time ? grid_.index_at_or_after(*config.start_time) : wall_index;
  const bool with_pps = !config.fast && (io ? io->pps != nullptr : config.pps.has_value());
  if (config.start_time && with_pps) {
    const UtcNs first = grid_.time_of(first_index_);
    const auto phase = first - std::chrono::floor<std::chrono::seconds>(first);
    const UtcNs first_wall =
        std::chrono::ceil<std::chrono::seconds>(now + std::chrono::milliseconds(1) - phase) + phase;
    sim_minus_wall_ = first - first_wall;
  } else {
    sim_minus_wall_ = grid_.time_of(first_index_) - grid_.time_of(wall_index);
  }
  const UtcNs first_epoch = grid_.time_of(first_index_);

  source_ = sources::make_source(config, frame_, first_epoch);
  receiver_ = std::make_unique<Receiver>(frame_, receiver_options(config),
                                         noise::make_noise_model(config.noise, config.seed), first_epoch);
  if (io) {
    outputs_ = std::move(io->outputs);
    if (with_pps) pps_ = std::move(io->pps);
  } else {
    open_outputs();
    if (with_pps) open_pps();
  }
  pps_width_ = std::chrono::nanoseconds{std::llround(config.pps_width_s * 1e9)};
  spdlog::info("source {}; noise {}; {} Hz, latency {} ms; first epoch {}", source_->describe(),
               noise::to_string(config.noise.model), config.rate_hz, config.latency_s * 1000.0,
               format_iso8601_utc(first_epoch));
  const Geometry& g = receiver_->geometry();
  spdlog::info("receiver: GGA quality {} (noise x{}), {} of {} satellites used, HDOP {:.2f}; {} bytes an epoch at most",
               static_cast<int>(config.receiver.quality), noise_scale(config.receiver.quality), g.satellites_used,
               g.satellites_in_view, g.hdop,
               nmea::line_budget(config.format, g.satellites_in_view, g.satellites_used, config.rate_hz).bytes_per_epoch);
  for (const auto& out : outputs_) spdlog::info("NMEA on {}", out->describe());
  if (pps_) {
    spdlog::info("PPS on {}: leading edge at each whole UTC second, {} ms wide, {}", pps_->describe(),
                 config.pps_width_s * 1000.0,
                 pps_->polarity() == transport::PpsPolarity::active_high ? "high during the pulse" : "low during the pulse");
  }
}

void Runner::open_outputs() {
  std::vector<transport::OutputSpec> specs;
  for (const std::string& text : config_.outputs) specs.push_back(transport::parse_output_spec(text));
  // Refuse a serial line that cannot carry the epochs before opening anything.
  std::optional<std::size_t> epoch_bytes;
  for (const auto& spec : specs) {
    if (spec.kind != transport::OutputKind::serial) continue;
    if (!epoch_bytes) epoch_bytes = worst_case_epoch_bytes(config_.format);
    check_serial_line_budget(spec, *epoch_bytes, config_.rate_hz);
  }
  for (const auto& spec : specs) {
    outputs_.push_back(transport::make_output(
        spec, transport::OutputOptions{.realtime = !config_.fast, .rate_hz = config_.rate_hz}));
  }
  if (config_.tee) outputs_.push_back(std::make_unique<transport::TeeOutput>(*config_.tee, !config_.fast));
}

void Runner::open_pps() {
  const transport::PpsSpec spec = transport::parse_pps_spec(*config_.pps);
  const auto polarity =
      config_.pps_active_low ? transport::PpsPolarity::active_low : transport::PpsPolarity::active_high;
  if (spec.kind == transport::PpsSpec::Kind::gpio) {
    pps_ = std::make_unique<transport::GpioPps>(spec.chip, spec.line, polarity);
    return;
  }
  for (const auto& out : outputs_) {
    if (auto* serial = dynamic_cast<transport::SerialOutput*>(out.get())) {
      pps_ = std::make_unique<transport::ModemPps>(*serial, spec.modem_line, polarity);
      return;
    }
  }
  throw std::runtime_error(fmt::format(
      "--pps {}: drives a modem line of the serial output, but there is no serial output: add --output "
      "serial:DEVICE[@BAUD] (a pty output has no modem lines; with one, use --pps gpio:CHIP:LINE)",
      transport::to_string(spec)));
}

Runner::~Runner() = default;

int Runner::run(const std::atomic<bool>& stop) {
  const auto latency = std::chrono::nanoseconds{std::llround(config_.latency_s * 1e9)};
  const std::int64_t count = config_.duration_s ? std::llround(*config_.duration_s * config_.rate_hz)
                                                : std::numeric_limits<std::int64_t>::max();
  std::string text;
  text.reserve(1024);
  if (pps_) {
    // The first pulse: the first whole second at or after the first epoch (in wall time).
    const UtcNs first_wall = grid_.time_of(first_index_) - sim_minus_wall_;
    next_edge_ = {std::chrono::ceil<std::chrono::seconds>(first_wall), true};
  }
  // --clock scaled:K / lockstep pace the epochs instead of the real-time code below (clock.hpp).
  SystemClockIo clock_io = clock_io_for(outputs_, *source_);
  const auto clock = make_epoch_clock(config_.clock, clock_io, *source_, grid_.time_of(first_index_),
                                      grid_.time_of(first_index_) - sim_minus_wall_ + latency, grid_.nominal_period());
  if (clock) spdlog::info("{}", clock->describe());
  for (std::int64_t k = 0; !stop.load() && k < count; ++k) {
    const UtcNs t = grid_.time_of(first_index_ + k);
    if (source_->ended_at(t)) break;
    if (clock) {
      const EpochWait wait = clock->wait_for(t, stop);
      if (wait == EpochWait::stopped) break;
      if (wait == EpochWait::skip) {
        ++stats_.epochs_late_skipped;
        continue;
      }
    } else if (!config_.fast) {
      const UtcNs deadline = t - sim_minus_wall_ + latency;
      // Every PPS edge due before the epoch's bytes goes first (a leading edge at the same
      // instant too: the NMEA of second S follows pulse S).
      if (pps_) run_pps_until(deadline, stop);
      if (stop.load()) break;
      // An epoch whose time has long passed (the process was stopped or starved) is skipped, not
      // sent late in a burst: a receiver never reports the past.
      if (wall_now() - deadline > grid_.nominal_period()) {
        ++stats_.epochs_late_skipped;
        spdlog::warn("epoch {} skipped: {} ms late", format_iso8601_utc(t),
                     std::chrono::duration_cast<std::chrono::milliseconds>(wall_now() - deadline).count());
        continue;
      }
      wait_until(deadline, stop);
      if (stop.load()) break;
    }
    source_->service();
    const nmea::Fix fix = receiver_->fix_at(t, source_->truth_at(t));
    if (!fix.has_fix()) ++stats_.epochs_without_fix;
    format_epoch(fix, config_.format, text);
    for (auto& out : outputs_) (void)out->write_epoch(text);
    ++stats_.epochs_emitted;
    if (config_.fast && (k & 0x3ff) == 0) service_all();
  }
  if (pps_ && pps_->pulse_on()) {
    // End the last pulse at its time (at once when stopped), never leave the line in a pulse.
    if (!stop.load()) wait_until(next_edge_.time, stop);
    pps_->set(false);
  }
  for (auto& out : outputs_) out->flush();
  log_summary();
  return 0;
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

void Runner::wait_until(UtcNs wall_deadline, const std::atomic<bool>& stop) {
  // Sleep in poll() while far from the deadline, servicing client input and sockets; the last
  // stretch is an absolute clock_nanosleep on CLOCK_REALTIME, so the deadline does not drift.
  std::vector<pollfd>& fds = poll_fds_;  // capacity kept between epochs
  constexpr auto kMargin = std::chrono::milliseconds(2);
  while (!stop.load()) {
    const auto remaining = wall_deadline - wall_now();
    if (remaining <= kMargin) break;
    // Rebuilt each time: servicing may close a descriptor (a serial device hung up) or open one.
    fds.clear();
    for (const auto& out : outputs_) {
      if (out->poll_fd() >= 0) fds.push_back({out->poll_fd(), POLLIN, 0});
    }
    if (source_->poll_fd() >= 0) fds.push_back({source_->poll_fd(), POLLIN, 0});
    if (fds.empty()) break;  // nothing to service: one wake-up, the absolute sleep below
    const int timeout_ms =
        static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(remaining - kMargin).count());
    const int ready = ::poll(fds.data(), fds.size(), std::max(timeout_ms, 0));
    if (ready > 0) service_all();
  }
  const std::int64_t ns = wall_deadline.time_since_epoch().count();
  const timespec ts{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
  while (!stop.load() && clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

void Runner::service_all() {
  for (auto& out : outputs_) out->service();
  source_->service();
}

void Runner::log_summary() const {
  spdlog::info("{} epochs emitted ({} without fix), {} late epochs skipped", stats_.epochs_emitted,
               stats_.epochs_without_fix, stats_.epochs_late_skipped);
  for (const auto& out : outputs_) {
    const auto& s = out->stats();
    spdlog::info("{}: {} epochs written ({} bytes), {} dropped, {} failed", out->describe(), s.epochs_written,
                 s.bytes_written, s.epochs_dropped, s.epochs_failed);
  }
  if (pps_) {
    spdlog::info("PPS {}: {} pulses, {} skipped late, {} edges failed; worst leading edge {:.3f} ms after its second",
                 pps_->describe(), stats_.pps_pulses, stats_.pps_pulses_late_skipped, pps_->stats().failures,
                 std::chrono::duration<double, std::milli>(stats_.pps_worst_edge_delay).count());
  }
}

}  // namespace gpsemu
