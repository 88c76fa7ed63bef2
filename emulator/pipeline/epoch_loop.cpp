#include "emulator/pipeline/epoch_loop.hpp"

#include <algorithm>
#include <functional>

#include <spdlog/spdlog.h>

namespace gpsemu {
namespace {

/// From this many receivers on, a second thread writes half of them at the deadline.
constexpr std::size_t kHelperWriterFrom = 8;
/// Shortest lead for computing many receivers' epochs ahead of the deadline.
constexpr std::chrono::microseconds kMinComputeLead{300};

}  // namespace

std::unique_ptr<SystemClockIo> make_loop_io(Sink& sink, EpochProducer& producer) {
  // What the k-th polled descriptor belongs to: an output, or an input of the producer.
  struct Pollables {
    std::vector<transport::Output*> outputs;
    std::vector<std::size_t> inputs;
  };
  auto polled = std::make_shared<Pollables>();
  return std::make_unique<SystemClockIo>(
      [&sink, &producer, polled](std::vector<int>& fds) {
        polled->outputs.clear();
        polled->inputs.clear();
        sink.list_inputs(fds, polled->outputs);
        producer.list_inputs(fds, polled->inputs);
      },
      SystemClockIo::ReadyServicer([&producer, polled](std::size_t k) {
        if (k < polled->outputs.size()) {
          polled->outputs[k]->service();
          polled->outputs[k]->answer_clients();
        } else {
          producer.service_input(polled->inputs[k - polled->outputs.size()]);
        }
      }));
}

EpochLoop::EpochLoop(EpochProducer& producer, Sink& sink, EpochClock& clock, LoopOptions options, PpsTimeline* pps)
    : producer_(producer), sink_(sink), clock_(clock), options_(options), pps_(pps) {}

EpochLoop::~EpochLoop() = default;

void EpochLoop::run(const std::atomic<bool>& stop) {
  const std::size_t n = sink_.receivers();
  const bool ahead = options_.compute_ahead_within.has_value() && n > 1;
  if (ahead && n >= kHelperWriterFrom && !helper_) {
    // Made here, by the thread that runs the loop, after main() applied --realtime-priority and
    // --timer-slack to it: the helper inherits them.
    helper_ = std::make_unique<HelperWriter>(
        [this](std::size_t first, std::size_t from, std::size_t to) { write_range(first, from, to); });
  }
  ahead_.assign(n, {});
  ClockIo* io = clock_.io();
  for (std::int64_t k = 0; !stop.load(); ++k) {
    UtcNs t{};
    if (!producer_.next_epoch(t)) break;
    if (!io) {
      if (!producer_.any_due()) continue;
      // Fast: nothing waits and nothing is polled; service client input and new clients now and then.
      if ((stats_.epochs_emitted & 0x3ff) == 0) {
        sink_.service_all();
        producer_.service_inputs();
        if (sink_.all_gone()) break;
      }
    } else if (const std::optional<UtcNs> idle_deadline = clock_.deadline_of(t); idle_deadline && !producer_.any_due()) {
      // An idle epoch: the ports answer until its time, nothing is sent. Every PPS edge due
      // before it goes first (a fleet drives them in run_ahead()).
      if (pps_ && !ahead) pps_->run_until(*idle_deadline, *io, stop);
      if (stop.load()) break;
      io->sleep_until_woken(*idle_deadline, stop, [this] { return producer_.reschedule_wanted(); });
      if (!stop.load()) (void)rescheduled(*io);
      continue;
    } else if (idle_deadline) {
      if (!ahead) send_delayed(io, *idle_deadline, stop);
      const EpochWait wait = wait_for_deadline(t, !ahead, stop);
      if (wait == EpochWait::stopped) break;
      if (wait == EpochWait::rescheduled) continue;
      if (wait == EpochWait::skip) {
        count_late();
        continue;
      }
      const UtcNs deadline = *clock_.deadline_of(t);
      if (ahead) {
        const std::function<bool()> woken = [this] { return producer_.reschedule_wanted(); };
        const EpochWait written = run_ahead(k, t, deadline, stop, woken);
        if (written == EpochWait::skip) count_late();
        if (written == EpochWait::due) ++stats_.epochs_emitted;
        if (written == EpochWait::stopped) break;
        continue;
      }
      if (options_.measure_send_delay) {
        // Against the deadline it could be met at: an epoch whose time went back is due with the
        // previous one, not at its own (past) deadline.
        latest_deadline_ = std::max(latest_deadline_, deadline);
        const auto delay = std::max(io->now() - latest_deadline_, std::chrono::nanoseconds::zero());
        stats_.worst_delay = std::max(stats_.worst_delay, delay);
        stats_.total_delay += delay;
      }
    } else {
      // Not on the wall clock (lockstep): the clock waits, servicing input meanwhile.
      const EpochWait wait = clock_.wait_for(t, stop);
      if (wait == EpochWait::stopped) break;
      if (!producer_.any_due()) continue;
      if (wait == EpochWait::skip) {
        count_late();
        continue;
      }
    }
    send(t);
    ++stats_.epochs_emitted;
    if (io && sink_.all_gone()) break;  // real time: a few virtual calls an epoch
  }
  if (!stop.load()) send_delayed(io, UtcNs::max(), stop);  // the last epochs a latency held back
  stats_.outputs_gone = sink_.all_gone();
  if (helper_) helper_->wait_done();
  if (pps_ && io) pps_->finish(*io, stop);
  sink_.flush();
}

int EpochLoop::exit_status() const {
  if (stats_.outputs_gone) {
    spdlog::error("every output is gone (the reader of the pipe closed it): stopped");
    return kExitOutputsGone;
  }
  if (stats_.epochs_emitted != 0 && sink_.none_took_any()) {
    spdlog::error("no output took any epoch (every write failed): exit status {}", kExitNothingWritten);
    return kExitNothingWritten;
  }
  return 0;
}

EpochWait EpochLoop::wait_for_deadline(UtcNs t, bool sleep, const std::atomic<bool>& stop) {
  ClockIo& io = *clock_.io();
  // A client's new solution period takes effect at once: the wait for an epoch on the old grid
  // ends and the next epoch is asked again (a new rate's first solution comes within one of its
  // periods, not at the next epoch of the old grid).
  const std::function<bool()> woken = [this] { return producer_.reschedule_wanted(); };
  for (;;) {
    // A wall clock that went back: the deadlines follow it (logged once a step), so the epochs
    // go on one period apart instead of waiting out the step.
    if (const auto back = clock_.follow_step_back(t, io.now()); back > std::chrono::nanoseconds::zero()) {
      ++stats_.clock_steps_back;
      spdlog::warn("the wall clock went back before epoch {}: its deadlines moved back {:.3f} s and the epochs go on "
                   "one period apart; their times are now {:.3f} s ahead of the system clock (a receiver's time never "
                   "goes back)",
                   format_iso8601_utc(t), std::chrono::duration<double>(back).count(),
                   std::chrono::duration<double>(clock_.moved_back()).count());
      if (pps_) pps_->start(io.now());
    }
    const UtcNs deadline = *clock_.deadline_of(t);
    // Every PPS edge due before the epoch's bytes goes first (a leading edge at the same instant
    // too: the NMEA of second S follows pulse S). A fleet drives them in run_ahead().
    if (pps_ && sleep) pps_->run_until(deadline, io, stop, &woken);
    if (stop.load()) return EpochWait::stopped;
    if (rescheduled(io)) return EpochWait::rescheduled;
    if (clock_.late(t)) return EpochWait::skip;
    if (!sleep) return EpochWait::due;
    io.sleep_until_woken(deadline, stop, woken);
    if (stop.load()) return EpochWait::stopped;
    if (rescheduled(io)) return EpochWait::rescheduled;
    // Woken at the deadline, or later (the process was stopped or starved, the wall clock jumped
    // ahead): an epoch more than a period late is skipped, never sent with its old time. Woken
    // before it: the wall clock was set; look again.
    if (io.now() >= deadline) return clock_.late(t) ? EpochWait::skip : EpochWait::due;
  }
}

bool EpochLoop::rescheduled(ClockIo& io) {
  if (!producer_.reschedule_wanted()) return false;
  const std::optional<UtcNs> now = clock_.epoch_time_at(io.now());
  if (!now) return false;
  producer_.reschedule(*now);
  clock_.abandon_current();
  ++stats_.reschedules;
  return true;
}

void EpochLoop::send(UtcNs t) {
  for (std::size_t i = 0; i < ahead_.size(); ++i) {
    if (producer_.active(i)) sink_.write(i, producer_.produce(i, t));
  }
}

void EpochLoop::send_delayed(ClockIo* io, UtcNs until, const std::atomic<bool>& stop) {
  for (;;) {
    std::optional<UtcNs> first;
    for (std::size_t i = 0; i < ahead_.size(); ++i) {
      const std::optional<UtcNs> due = producer_.delayed_until(i);
      if (due && (!first || *due < *first)) first = due;
    }
    if (!first) return;
    const std::optional<UtcNs> wall = io ? clock_.deadline_of(*first) : std::nullopt;
    if (wall) {
      if (*wall >= until) return;
      if (pps_) pps_->run_until(*wall, *io, stop);
      io->sleep_until(*wall, stop);
      if (stop.load()) return;
    } else if (until != UtcNs::max()) {
      return;  // not on the wall clock: each epoch's produce() writes what is due, the rest at the end
    }
    for (std::size_t i = 0; i < ahead_.size(); ++i) {
      const std::string_view bytes = producer_.take_delayed(i, *first);
      if (!bytes.empty()) sink_.write(i, bytes);
    }
  }
}

void EpochLoop::write_range(std::size_t first, std::size_t from, std::size_t to) {
  const std::size_t n = ahead_.size();
  for (std::size_t pos = from; pos < to; ++pos) {
    const std::size_t i = (first + pos) % n;
    if (producer_.active(i)) sink_.write(i, ahead_[i]);
  }
}

EpochWait EpochLoop::run_ahead(std::int64_t k, UtcNs t, UtcNs deadline, const std::atomic<bool>& stop,
                               const std::function<bool()>& woken) {
  ClockIo& io = *clock_.io();
  // Compute ahead by twice the recent cost, within the latency: never before the epoch's own time
  // (a receiver's fix for t is computed after t), so with no latency it is done at the deadline.
  const auto lead = std::clamp(2 * compute_cost_ + kMinComputeLead, std::chrono::nanoseconds{0},
                               *options_.compute_ahead_within);
  const UtcNs compute_at = deadline - lead;
  // A `latency`'s held-back bytes due before the computing, each at its own time, as a single
  // receiver writes them (the helper writer is idle now; the rest leave with this epoch).
  send_delayed(&io, compute_at, stop);
  if (stop.load()) return EpochWait::stopped;
  if (pps_) pps_->run_until(compute_at, io, stop, &woken);
  if (stop.load()) return EpochWait::stopped;
  if (rescheduled(io)) return EpochWait::rescheduled;
  io.sleep_until_woken(compute_at, stop, woken);
  if (stop.load()) return EpochWait::stopped;
  if (rescheduled(io)) return EpochWait::rescheduled;
  const auto begin = std::chrono::steady_clock::now();
  const std::size_t n = ahead_.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!producer_.active(i)) continue;
    ahead_[i] = producer_.produce(i, t);
    sink_.prepare(i);
  }
  const auto cost = std::chrono::steady_clock::now() - begin;
  // A decaying maximum: one slow epoch raises the lead at once, which then shrinks by 1% an epoch.
  compute_cost_ = std::max(std::chrono::nanoseconds{cost}, compute_cost_ * 99 / 100);
  const std::size_t first = static_cast<std::size_t>(k % static_cast<std::int64_t>(n));
  const std::size_t mine = helper_ ? n / 2 : n;
  // Woken more than a period after the deadline (stopped, starved, the wall clock jumped): the
  // epoch is skipped by both writers, never sent with its old time.
  const UtcNs latest = deadline + clock_.epoch_period();
  if (helper_) helper_->post(deadline, first, mine, n, latest);
  if (pps_) pps_->run_until(deadline, io, stop);
  io.sleep_until(deadline, stop);
  // Stopped while waiting: the helper still writes its part at the deadline; write ours too, so
  // an epoch is never half sent.
  const bool late = io.now() > latest;
  if (!late) write_range(first, 0, mine);
  if (helper_) helper_->wait_done();
  if (stop.load()) return EpochWait::stopped;
  return late ? EpochWait::skip : EpochWait::due;
}

}  // namespace gpsemu
