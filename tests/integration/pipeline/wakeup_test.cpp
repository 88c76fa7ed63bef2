// One wake-up per epoch: the epoch loop waits for each epoch on an absolute CLOCK_REALTIME timerfd
// (transport/posix/wait.hpp), polled with its inputs or read alone when there are none, so with no
// input arriving it wakes exactly once an epoch (no early wake-up followed by a final sleep, no
// spinning on a sub-millisecond poll timeout). Counts, not times: every wait that returned counts.
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <netinet/in.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "emulator/pipeline/clock.hpp"
#include "emulator/config/config.hpp"
#include "emulator/pipeline/runner.hpp"
#include "tests/support/scratch.hpp"
#include "transport/pty_output.hpp"
#include "transport/recording_output.hpp"

namespace gpsemu {
namespace {
namespace wakeup_test {

using namespace std::chrono_literals;

Config config_for(RawOptions options) {
  options.push_back({"log-level", {"warn"}});
  return build_config(std::nullopt, options);
}

TEST(Wakeup, OneAnEpochWithNothingToService) {
  const Config config = config_for({{"rate", {"10"}}, {"duration", {"1"}}});
  RunnerIo io;
  auto out = std::make_unique<transport::RecordingOutput>();
  transport::RecordingOutput* recorded = out.get();
  io.outputs.push_back(std::move(out));
  Runner runner(config, std::move(io));
  std::atomic<bool> stop{false};
  ASSERT_EQ(runner.run(stop), 0);
  EXPECT_EQ(recorded->epochs.size(), 10u);
  EXPECT_EQ(runner.stats().epochs_emitted + runner.stats().epochs_late_skipped, 10u);
  // A late-skipped epoch is not waited for, nor one whose deadline had passed when the loop came to
  // it (a slow start on a busy machine): every other emitted epoch is exactly one wake-up.
  EXPECT_EQ(runner.stats().wakeups + runner.stats().waits_already_due, runner.stats().epochs_emitted);
}

TEST(Wakeup, OneAnEpochOnAPtyWithoutClient) {
  const auto link = test::scratch_root() / ("gpsemu_wakeup_" + std::to_string(::getpid()));
  const Config config = config_for({{"rate", {"10"}}, {"duration", {"1"}}});
  RunnerIo io;
  io.outputs.push_back(std::make_unique<transport::PtyOutput>(link));
  Runner runner(config, std::move(io));
  std::atomic<bool> stop{false};
  ASSERT_EQ(runner.run(stop), 0);
  EXPECT_EQ(runner.stats().epochs_emitted + runner.stats().epochs_late_skipped, 10u);
  // An epoch whose deadline had passed when the loop came to it (a slow start on a busy machine)
  // needs no wait: every other one exactly one wake-up.
  EXPECT_EQ(runner.stats().wakeups + runner.stats().waits_already_due, runner.stats().epochs_emitted);
}

TEST(Wakeup, InputIsServicedWhileWaitingAndTheDeadlineStillHolds) {
  // A datagram arriving during the wait wakes the poll, is serviced, and the wait goes on to the
  // deadline: two wake-ups, and the wait does not return before the deadline.
  const int rx = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
  ASSERT_GE(rx, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(rx, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  socklen_t len = sizeof addr;
  ASSERT_EQ(::getsockname(rx, reinterpret_cast<sockaddr*>(&addr), &len), 0);
  int serviced = 0;
  SystemClockIo io([rx](std::vector<int>& fds) { fds.push_back(rx); },
                   [rx, &serviced] {
                     char buf[64];
                     while (::recv(rx, buf, sizeof buf, 0) > 0) ++serviced;
                   });
  const UtcNs deadline = system_utc_now() + 300ms;
  std::thread sender([addr] {
    std::this_thread::sleep_for(50ms);
    const int tx = ::socket(AF_INET, SOCK_DGRAM, 0);
    (void)::sendto(tx, "x", 1, 0, reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
    ::close(tx);
  });
  std::atomic<bool> stop{false};
  io.sleep_until(deadline, stop);
  const UtcNs woke = system_utc_now();
  sender.join();
  ::close(rx);
  EXPECT_EQ(serviced, 1);
  EXPECT_GE(woke, deadline);
  EXPECT_EQ(io.wakeups(), 2u);
}

TEST(Wakeup, StopEndsTheWait) {
  SystemClockIo io([](std::vector<int>&) {}, [] {});
  std::atomic<bool> stop{true};
  const UtcNs before = system_utc_now();
  io.sleep_until(before + 10s, stop);
  EXPECT_LT(system_utc_now() - before, 5s);
  EXPECT_EQ(io.wakeups(), 0u);
}

TEST(Wakeup, PastDeadlineReturnsAtOnce) {
  SystemClockIo io([](std::vector<int>&) {}, [] {});
  std::atomic<bool> stop{false};
  io.sleep_until(system_utc_now() - 1s, stop);
  EXPECT_EQ(io.wakeups(), 0u);
}

}  // namespace wakeup_test
}  // namespace
}  // namespace gpsemu
