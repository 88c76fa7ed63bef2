// The epoch loop when the wall clock is stepped (issue 22 points 5 and 6): the real EpochLoop,
// RealtimeClock and Sink, with a wall clock the test steps (the system clock cannot be stepped on
// a shared machine). A wait ends when the clock is set, as the loop's timerfd does
// (TFD_TIMER_CANCEL_ON_SET). Stepped back 30 s at 10 Hz: the epochs go on one period apart with
// increasing times, none skipped, the step counted once (no 30 s of silence); with PPS the
// deadlines move by whole seconds; a step of less than half a period is waited out; replay's
// scaled clock follows a step exactly. Stepped ahead 30 s: the epoch being waited for and the
// 30 s after it are skipped and counted; nothing is written with a time more than a period old.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emulator/model/time.hpp"
#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/epoch_loop.hpp"
#include "emulator/pipeline/sink.hpp"
#include "transport/output.hpp"

namespace gpsemu {
namespace {
namespace clock_step_test {

using namespace std::chrono_literals;
using std::chrono::nanoseconds;

/// A wall clock that moves only when waited on, and jumps by `step` when it reaches `step_at`
/// (a wait across that instant ends there, as a set clock ends a timerfd wait). `elapsed` is the
/// time that really passed (what a monotonic clock reads).
class SteppedClockIo final : public ClockIo {
 public:
  SteppedClockIo(UtcNs start, UtcNs step_at, nanoseconds step) : now_(start), step_at_(step_at), step_(step) {}

  UtcNs now() override { return now_; }
  void sleep_until(UtcNs deadline, const std::atomic<bool>& /*stop*/) override { advance_to(deadline); }
  void wait_for_input(nanoseconds timeout, const std::atomic<bool>& /*stop*/) override { advance_to(now_ + timeout); }
  [[nodiscard]] nanoseconds elapsed() const { return elapsed_; }

 private:
  void advance_to(UtcNs target) {
    if (target <= now_) return;
    if (step_at_ && *step_at_ > now_ && *step_at_ <= target) {
      elapsed_ += *step_at_ - now_;
      now_ = *step_at_ + step_;
      step_at_.reset();
      return;  // woken by the step
    }
    elapsed_ += target - now_;
    now_ = target;
  }
  UtcNs now_;
  std::optional<UtcNs> step_at_;
  nanoseconds step_;
  nanoseconds elapsed_{0};
};

/// Epochs every 100 ms from t0; each epoch's bytes are its index.
class GridProducer final : public EpochProducer {
 public:
  GridProducer(UtcNs t0, int epochs) : t0_(t0), epochs_(epochs) {}
  bool next_epoch(UtcNs& t) override {
    if (k_ >= epochs_) return false;
    t = t0_ + k_++ * 100ms;
    return true;
  }
  std::string_view produce(std::size_t /*i*/, UtcNs t) override {
    text_ = std::to_string((t - t0_) / 100ms);
    return text_;
  }

 private:
  UtcNs t0_;
  int epochs_;
  int k_ = 0;
  std::string text_;
};

/// Keeps each epoch written with the wall time and the elapsed time it was written at.
class TimedOutput final : public transport::Output {
 public:
  explicit TimedOutput(SteppedClockIo& io) : io_(io) {}
  struct Written {
    int index;
    UtcNs wall;
    nanoseconds elapsed;
  };
  std::vector<Written> written;
  [[nodiscard]] std::string describe() const override { return "timed"; }

 protected:
  transport::WriteStatus write_bytes(std::string_view bytes, std::string& /*error_text*/) override {
    written.push_back({std::stoi(std::string(bytes)), io_.now(), io_.elapsed()});
    return transport::WriteStatus::ok;
  }

 private:
  SteppedClockIo& io_;
};

struct SteppedRun {
  std::vector<TimedOutput::Written> written;
  LoopStats stats;
};

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

/// 60 epochs at 10 Hz from t0 (latency 50 ms) on the clock `make_clock(io)` makes; the wall clock
/// jumps by `step` at t0 + 1.07 s.
template <class MakeClock>
SteppedRun run_with_step(nanoseconds step, MakeClock make_clock) {
  const UtcNs t0 = kT0;
  SteppedClockIo io(t0 - 30ms, t0 + 1070ms, step);
  auto clock_ptr = make_clock(io);
  EpochClock& clock = *clock_ptr;
  GridProducer producer(t0, 60);
  Sink sink;
  auto out = std::make_unique<TimedOutput>(io);
  TimedOutput* timed = out.get();
  std::vector<std::unique_ptr<transport::Output>> outputs;
  outputs.push_back(std::move(out));
  (void)sink.add(std::move(outputs));
  EpochLoop loop(producer, sink, clock, {});
  const std::atomic<bool> stop{false};
  loop.run(stop);
  return {timed->written, loop.stats()};
}

SteppedRun run_with_step(nanoseconds step) {
  return run_with_step(step, [](ClockIo& io) { return std::make_unique<RealtimeClock>(io, 0ns, 50ms, 100ms); });
}

TEST(ClockStep, BackwardsTheEpochsGoOnOnePeriodApart) {
  const SteppedRun run = run_with_step(-30s);
  ASSERT_EQ(run.written.size(), 60u) << "every epoch written, none skipped";
  EXPECT_EQ(run.stats.epochs_late_skipped, 0u);
  EXPECT_EQ(run.stats.clock_steps_back, 1u);
  for (std::size_t k = 1; k < run.written.size(); ++k) {
    EXPECT_EQ(run.written[k].index, run.written[k - 1].index + 1);
    // No silence for the size of the step: one period between writes, as before it.
    EXPECT_LE(run.written[k].elapsed - run.written[k - 1].elapsed, 100ms) << "epoch " << run.written[k].index;
  }
  // After the step the epochs leave one period apart on the new wall clock: the deadlines moved
  // back by whole periods (at least the step), so each epoch's phase on the wall clock is kept.
  const auto& last = run.written.back();
  const nanoseconds behind = (parse_iso8601_utc("2024-05-01T12:00:00Z") + last.index * 100ms + 50ms) - last.wall;
  EXPECT_GE(behind, 30s);
  EXPECT_LT(behind, 30s + 100ms);
  EXPECT_EQ(behind % 100ms, 0ns);
}

TEST(ClockStep, AheadTheStaleEpochsAreSkippedAndCounted) {
  const SteppedRun run = run_with_step(30s);
  const UtcNs t0 = parse_iso8601_utc("2024-05-01T12:00:00Z");
  // Before the step: epochs 0..10 (deadline 1.05 s); at 1.07 s the clock reads 31.07 s: every
  // epoch up to 30.9 s is more than a period late. 60 epochs end at 5.9 s: all later are skipped.
  EXPECT_EQ(run.written.size(), 11u);
  EXPECT_EQ(run.stats.epochs_late_skipped, 49u);
  EXPECT_EQ(run.stats.epochs_emitted + run.stats.epochs_late_skipped, 60u);
  for (const auto& w : run.written) {
    EXPECT_LE(w.wall - (t0 + w.index * 100ms + 50ms), 100ms) << "epoch " << w.index << " sent with an old time";
  }
}

// With PPS the deadlines move by whole seconds (epoch S still follows pulse S): after 30.4 s back,
// 31 s; the epochs whose deadlines then lie more than a period behind are skipped, within a second.
TEST(ClockStep, BackwardsWithPpsTheDeadlinesMoveByWholeSeconds) {
  const SteppedRun run = run_with_step(-30400ms, [](ClockIo& io) {
    return std::make_unique<RealtimeClock>(io, 0ns, 50ms, 100ms, std::chrono::seconds{1});
  });
  EXPECT_EQ(run.stats.clock_steps_back, 1u);
  const auto& last = run.written.back();
  EXPECT_EQ((kT0 + last.index * 100ms + 50ms) - last.wall, 31s);
  for (std::size_t k = 1; k < run.written.size(); ++k) {
    EXPECT_LE(run.written[k].elapsed - run.written[k - 1].elapsed, 1s) << "epoch " << run.written[k].index;
  }
  EXPECT_EQ(run.written.size() + run.stats.epochs_late_skipped, 60u);
}

// A step back smaller than half a period is waited out (less than a period), not followed.
TEST(ClockStep, BackwardsByLessThanHalfAPeriodIsWaitedOut) {
  const SteppedRun run = run_with_step(-40ms);
  EXPECT_EQ(run.stats.clock_steps_back, 0u);
  EXPECT_EQ(run.written.size(), 60u);
  for (std::size_t k = 1; k < run.written.size(); ++k) {
    EXPECT_LE(run.written[k].elapsed - run.written[k - 1].elapsed, 140ms);
  }
}

// Replay's clock (scaled, never skipping) follows a step back exactly: every epoch is sent, the
// one after the step a period after the step was seen (here 20 ms after the epoch before it).
TEST(ClockStep, ReplaysScaledClockFollowsAStepBack) {
  const SteppedRun run = run_with_step(-30s, [](ClockIo& io) {
    return std::make_unique<ScaledClock>(io, 1.0, kT0, kT0 + 50ms, 100ms, /*skip_late=*/false);
  });
  ASSERT_EQ(run.written.size(), 60u);
  EXPECT_EQ(run.stats.clock_steps_back, 1u);
  for (std::size_t k = 1; k < run.written.size(); ++k) {
    EXPECT_LE(run.written[k].elapsed - run.written[k - 1].elapsed, run.written[k].index == 11 ? 120ms : 100ms)
        << "epoch " << run.written[k].index;
  }
}

}  // namespace clock_step_test
}  // namespace
}  // namespace gpsemu
