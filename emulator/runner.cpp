#include "emulator/runner.hpp"

#include <poll.h>
#include <time.h>

#include <cerrno>
#include <cmath>
#include <limits>

#include <spdlog/spdlog.h>

#include "emulator/epoch_text.hpp"
#include "emulator/sources/make_source.hpp"
#include "transport/output_spec.hpp"

namespace gpsemu {
namespace {

UtcNs wall_now() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return UtcNs{std::chrono::nanoseconds{static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec}};
}

}  // namespace

Runner::Runner(const Config& config) : config_(config), grid_(config.rate_hz), frame_(config.origin) {
  const UtcNs now = wall_now();
  // The first epoch: the next grid epoch after now, or after --start-time. With --start-time in
  // real time, epoch times are shifted by a whole number of epochs from the wall clock, so the
  // sub-second phase of every epoch still matches the wall clock (and a PPS line).
  const std::int64_t wall_index = grid_.index_at_or_after(now + std::chrono::milliseconds(1));
  first_index_ = config.start_time ? grid_.index_at_or_after(*config.start_time) : wall_index;
  sim_minus_wall_ = grid_.time_of(first_index_) - grid_.time_of(wall_index);
  const UtcNs first_epoch = grid_.time_of(first_index_);

  source_ = sources::make_source(config, frame_, first_epoch);
  receiver_ = std::make_unique<Receiver>(frame_, config.receiver,
                                         noise::make_noise_model(config.noise, config.seed), first_epoch);
  for (const std::string& spec : config.outputs) {
    outputs_.push_back(transport::make_output(transport::parse_output_spec(spec),
                                              transport::OutputOptions{.realtime = !config.fast}));
  }
  spdlog::info("source {}; noise {}; {} Hz, latency {} ms; first epoch {}", source_->describe(),
               noise::to_string(config.noise.model), config.rate_hz, config.latency_s * 1000.0,
               format_iso8601_utc(first_epoch));
  for (const auto& out : outputs_) spdlog::info("NMEA on {}", out->describe());
}

Runner::~Runner() = default;

int Runner::run(const std::atomic<bool>& stop) {
  const auto latency = std::chrono::nanoseconds{std::llround(config_.latency_s * 1e9)};
  const std::int64_t count = config_.duration_s ? std::llround(*config_.duration_s * config_.rate_hz)
                                                : std::numeric_limits<std::int64_t>::max();
  std::string text;
  text.reserve(1024);
  for (std::int64_t k = 0; !stop.load() && k < count; ++k) {
    const UtcNs t = grid_.time_of(first_index_ + k);
    if (!config_.fast) {
      const UtcNs deadline = t - sim_minus_wall_ + latency;
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
  for (auto& out : outputs_) out->flush();
  log_summary();
  return 0;
}

void Runner::wait_until(UtcNs wall_deadline, const std::atomic<bool>& stop) {
  // Sleep in poll() while far from the deadline, servicing client input and sockets; the last
  // stretch is an absolute clock_nanosleep on CLOCK_REALTIME, so the deadline does not drift.
  std::vector<pollfd> fds;
  for (const auto& out : outputs_) {
    if (out->poll_fd() >= 0) fds.push_back({out->poll_fd(), POLLIN, 0});
  }
  if (source_->poll_fd() >= 0) fds.push_back({source_->poll_fd(), POLLIN, 0});
  constexpr auto kMargin = std::chrono::milliseconds(2);
  while (!stop.load()) {
    const auto remaining = wall_deadline - wall_now();
    if (remaining <= kMargin) break;
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
}

}  // namespace gpsemu
