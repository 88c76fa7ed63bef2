// --clock scaled:K: epochs paced at K times real time from the start while the NMEA times still
// advance one epoch period per epoch. The clock on a fake wall clock (deadlines, late epochs
// skipped), the --clock parser, and end to end through the binary (spacing measured on stdout).
#include <gtest/gtest.h>

#include <cmath>

#include <fmt/format.h>

#include "emulator/pipeline/clock.hpp"
#include "tests/support/process.hpp"

namespace gpsemu {
namespace {
namespace clock_scaled_test {

using namespace std::chrono;

const UtcNs kEpoch0 = parse_iso8601_utc("2024-05-01T12:00:00Z");
const UtcNs kWall0 = parse_iso8601_utc("2030-01-01T00:00:00.05Z");

class FakeWall final : public ClockIo {
 public:
  UtcNs now() override { return t; }
  void sleep_until(UtcNs deadline, const std::atomic<bool>&) override {
    sleeps.push_back(deadline);
    t = std::max(t, deadline);
  }
  void wait_for_input(nanoseconds timeout, const std::atomic<bool>&) override { t += timeout; }
  UtcNs t = kWall0;
  std::vector<UtcNs> sleeps;
};

TEST(ClockSpec, ParsesTheFourClocksAndRefusesTheRestNamingTheForms) {
  EXPECT_EQ(parse_clock_spec("realtime"), ClockSpec{});
  EXPECT_EQ(parse_clock_spec("fast").kind, ClockKind::fast);
  EXPECT_EQ(parse_clock_spec("lockstep").kind, ClockKind::lockstep);
  EXPECT_EQ(parse_clock_spec("scaled:2"), (ClockSpec{ClockKind::scaled, 2.0}));
  EXPECT_EQ(parse_clock_spec("scaled:0.5"), (ClockSpec{ClockKind::scaled, 0.5}));
  EXPECT_EQ(to_string(parse_clock_spec("scaled:0.5")), "scaled:0.5");
  for (const char* bad : {"", "scaled", "scaled:", "scaled:x", "scaled:0", "scaled:-1", "scaled:1001", "scaled:2x",
                          "Realtime", "stepped"}) {
    EXPECT_THROW((void)parse_clock_spec(bad), std::invalid_argument) << bad;
  }
}

TEST(ScaledClock, EpochsAreDueAtTheFirstDeadlinePlusEpochTimeOverK) {
  for (const double k : {4.0, 0.5}) {
    FakeWall wall;
    ScaledClock clock(wall, k, kEpoch0, kWall0, milliseconds(100));
    const std::atomic<bool> stop{false};
    for (int i = 0; i < 30; ++i) {
      ASSERT_EQ(clock.wait_for(kEpoch0 + milliseconds(100) * i, stop), EpochWait::due);
      EXPECT_EQ(wall.sleeps.back(), kWall0 + nanoseconds{std::llround(1e8 * i / k)}) << k << " " << i;
    }
  }
}

TEST(ScaledClock, AnEpochLateByMoreThanOneScaledPeriodIsSkippedNotSentInABurst) {
  FakeWall wall;
  ScaledClock clock(wall, 2.0, kEpoch0, kWall0, seconds(1));
  const std::atomic<bool> stop{false};
  EXPECT_EQ(clock.wait_for(kEpoch0, stop), EpochWait::due);
  wall.t = kWall0 + milliseconds(1100);  // the process stalled: epoch 1 (due at 0.5 s) is 0.6 s late
  EXPECT_EQ(clock.wait_for(kEpoch0 + seconds(1), stop), EpochWait::skip) << "over one scaled period (0.5 s) late";
  EXPECT_EQ(clock.wait_for(kEpoch0 + seconds(2), stop), EpochWait::due) << "due at 1 s, 0.1 s late: sent";
  EXPECT_EQ(clock.wait_for(kEpoch0 + seconds(4), stop), EpochWait::due);
  EXPECT_EQ(wall.t, kWall0 + seconds(2));
}

double time_of_day_s(const std::string& hhmmss) {
  return std::stoi(hhmmss.substr(0, 2)) * 3600.0 + std::stoi(hhmmss.substr(2, 2)) * 60.0 + std::stod(hhmmss.substr(4));
}

/// Runs gpsemu with --clock scaled:K; returns (NMEA time of day, wall read time) of each GGA.
std::vector<std::pair<double, double>> run_scaled(const std::string& clock, double rate_hz, double duration_s) {
  test::Process gpsemu({GPSEMU_BINARY, "--clock", clock, "--rate", fmt::format("{}", rate_hz), "--duration",
                        fmt::format("{}", duration_s), "--sentences", "GGA", "--output", "stdout", "--start-time",
                        "2024-05-01T12:00:00Z", "--log-level", "warn"});
  EXPECT_EQ(gpsemu.wait(seconds(60)), 0) << gpsemu.stderr_text();
  std::vector<std::pair<double, double>> out;
  for (const auto& c : gpsemu.chunks()) {
    for (std::size_t at = c.bytes.find("$GNGGA,"); at != std::string::npos; at = c.bytes.find("$GNGGA,", at + 1)) {
      out.emplace_back(time_of_day_s(c.bytes.substr(at + 7, 9)), c.read_s);
    }
  }
  return out;
}

TEST(ScaledClockEndToEnd, ScaledFourAt1HzSendsOneSecondOfEpochsEvery250ms) {
  const auto epochs = run_scaled("scaled:4", 1.0, 8.0);
  ASSERT_EQ(epochs.size(), 8u);
  double worst_ms = 0.0;
  for (std::size_t i = 1; i < epochs.size(); ++i) {
    EXPECT_NEAR(epochs[i].first - epochs[i - 1].first, 1.0, 1e-9) << "NMEA times advance 1 s an epoch";
    worst_ms = std::max(worst_ms, std::abs(1000.0 * (epochs[i].second - epochs[i - 1].second) - 250.0));
  }
  EXPECT_NEAR(epochs.front().first, 12 * 3600.0, 1e-9);
  // Paced at 4x: 7 gaps of 250 ms (real time would take 7 s, fast none). The span, not each gap,
  // with room for a loaded machine waking one epoch late: the spacing figure is printed only.
  const double span_s = epochs.back().second - epochs.front().second;
  EXPECT_GT(span_s, 1.75 - 0.3);
  EXPECT_LT(span_s, 1.75 + 1.0);
  ::testing::Test::RecordProperty("worst_spacing_error_ms", fmt::format("{:.2f}", worst_ms));
  std::printf("[ info ] scaled:4 at 1 Hz: spacing within %.2f ms of 250 ms\n", worst_ms);
}

TEST(ScaledClockEndToEnd, ScaledHalfAt10HzSendsEpochs200msApartWithTimes100msApart) {
  const auto epochs = run_scaled("scaled:0.5", 10.0, 1.0);
  ASSERT_EQ(epochs.size(), 10u);
  double worst_ms = 0.0;
  for (std::size_t i = 1; i < epochs.size(); ++i) {
    EXPECT_NEAR(epochs[i].first - epochs[i - 1].first, 0.1, 1e-6);
    worst_ms = std::max(worst_ms, std::abs(1000.0 * (epochs[i].second - epochs[i - 1].second) - 200.0));
  }
  // Paced at half speed: 9 gaps of 200 ms (real time: 100 ms). The span, not each gap (a loaded
  // machine may wake one epoch late; under ASan one gap came 32 ms off): the spacing is printed.
  const double span_s = epochs.back().second - epochs.front().second;
  EXPECT_GT(span_s, 1.8 - 0.3);
  EXPECT_LT(span_s, 1.8 + 1.0);
  std::printf("[ info ] scaled:0.5 at 10 Hz: spacing within %.2f ms of 200 ms\n", worst_ms);
}

TEST(ScaledClockEndToEnd, SocketSourcesAndPpsAreRefused) {
  test::Process udp({GPSEMU_BINARY, "--clock", "scaled:2", "--source", "udp:0", "--output", "stdout"});
  EXPECT_EQ(udp.wait(seconds(20)), 2);
  EXPECT_NE(udp.stderr_text().find("cannot be used with --clock scaled:2"), std::string::npos) << udp.stderr_text();
  test::Process pps({GPSEMU_BINARY, "--clock", "scaled:2", "--pps", "modem:RTS", "--output", "stdout"});
  EXPECT_EQ(pps.wait(seconds(20)), 2);
  EXPECT_NE(pps.stderr_text().find("pps: a PPS pulse marks real seconds; it cannot be used with --clock scaled:2"),
            std::string::npos) << pps.stderr_text();
}

}  // namespace clock_scaled_test
}  // namespace
}  // namespace gpsemu
