// --clock lockstep: epochs follow the simulator's time stamps. The clock on a fake source and
// wall clock (due exactly when sim time reaches the epoch, whatever the wall clock does; the
// start skips what the simulator had already passed), the socket source's sender-time base
// (poses placed at base + t, poses without t refused), and end to end through the binary: a UDP
// sender whose sim time runs at half real speed gives NMEA times that follow sim time exactly,
// every epoch once, in order, at the wall spacing the simulator set.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <cmath>
#include <deque>
#include <map>

#include <fmt/format.h>

#include "emulator/pipeline/clock.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/sources/socket_source.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace clock_lockstep_test {

using namespace std::chrono;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");
UtcNs at_s(double s) { return kT0 + nanoseconds{std::llround(s * 1e9)}; }

// ---- the clock on fakes ----------------------------------------------------------------------

class FakeSimSource final : public sources::PoseSource {
 public:
  std::optional<sources::Truth> truth_at(UtcNs) override { return std::nullopt; }
  std::string describe() const override { return "fake"; }
  std::optional<UtcNs> sim_time() const override { return sim; }
  std::optional<UtcNs> sim;
};

/// Each wait for input: the wall clock moves 10 ms, the simulator `sim_step` (a pose arrives).
class SimulatorIo final : public ClockIo {
 public:
  SimulatorIo(FakeSimSource& source, nanoseconds sim_step) : source_(source), step_(sim_step) {}
  UtcNs now() override { return wall; }
  void sleep_until(UtcNs deadline, const std::atomic<bool>&) override { wall = std::max(wall, deadline); }
  void wait_for_input(nanoseconds, const std::atomic<bool>&) override {
    wall += milliseconds(10);
    source_.sim = source_.sim ? *source_.sim + step_ : kT0;
    ++waits;
  }
  UtcNs wall = parse_iso8601_utc("2030-01-01T00:00:00Z");
  int waits = 0;

 private:
  FakeSimSource& source_;
  nanoseconds step_;
};

TEST(LockstepClock, AnEpochIsDueExactlyWhenSimTimeReachesItAtAnySimulatorSpeed) {
  for (const double sim_per_wall : {0.5, 3.0}) {
    FakeSimSource source;
    SimulatorIo io(source, nanoseconds{std::llround(10e6 * sim_per_wall)});
    LockstepClock clock(io, source, milliseconds(200));
    const std::atomic<bool> stop{false};
    for (int k = 0; k < 20; ++k) {
      const UtcNs t = at_s(0.2 * k);
      ASSERT_EQ(clock.wait_for(t, stop), EpochWait::due) << k;
      ASSERT_TRUE(source.sim);
      EXPECT_GE(*source.sim, t) << k;
      EXPECT_LT(*source.sim - t, nanoseconds{std::llround(10e6 * sim_per_wall)}) << "due as soon as sim time reached it";
    }
    // Wall time taken follows the simulator: 3.8 s of sim time.
    const double wall_s = duration<double>(io.wall - parse_iso8601_utc("2030-01-01T00:00:00Z")).count();
    EXPECT_NEAR(wall_s, 3.8 / sim_per_wall, 0.02 + 0.01 / sim_per_wall) << sim_per_wall;
  }
}

TEST(LockstepClock, AtStartEpochsTheSimulatorHasAlreadyPassedAreSkippedThenNone) {
  FakeSimSource source;
  source.sim = at_s(10.55);  // the simulator was already running
  SimulatorIo io(source, milliseconds(5));
  LockstepClock clock(io, source, milliseconds(200));
  const std::atomic<bool> stop{false};
  int skipped = 0;
  int k = 0;
  for (; clock.wait_for(at_s(0.2 * k), stop) == EpochWait::skip; ++k) ++skipped;
  EXPECT_EQ(k, 52) << "the latest epoch sim time has reached (10.4 s) is the first one due";
  EXPECT_EQ(skipped, 52);
  // Then, even if sim time leaps ahead, every epoch is due in turn.
  source.sim = at_s(20.0);
  for (++k; k < 100; ++k) EXPECT_EQ(clock.wait_for(at_s(0.2 * k), stop), EpochWait::due) << k;
}

TEST(LockstepClock, WaitsForTheFirstPoseAndStops) {
  FakeSimSource source;
  class NoPoses final : public ClockIo {
   public:
    explicit NoPoses(std::atomic<bool>& stop) : stop_(stop) {}
    UtcNs now() override { return {}; }
    void sleep_until(UtcNs, const std::atomic<bool>&) override {}
    void wait_for_input(nanoseconds, const std::atomic<bool>&) override {
      if (++waits == 50) stop_.store(true);
    }
    int waits = 0;

   private:
    std::atomic<bool>& stop_;
  };
  std::atomic<bool> stop{false};
  NoPoses io(stop);
  LockstepClock clock(io, source, milliseconds(100));
  EXPECT_EQ(clock.wait_for(kT0, stop), EpochWait::stopped);
  EXPECT_EQ(io.waits, 50);
}

// ---- the socket source's sender-time base ------------------------------------------------------

class ScriptedSocket final : public transport::PoseSocket {
 public:
  /// Message bytes and arrival; the views handed out stay valid until the next receive().
  std::deque<std::pair<std::string, UtcNs>> queue;
  std::optional<transport::ReceivedMessage> receive() override {
    if (queue.empty()) return std::nullopt;
    current_ = queue.front();
    queue.pop_front();
    transport::ReceivedMessage m;
    m.kind = transport::ReceivedMessage::Kind::message;
    m.bytes = current_.first;
    m.arrival = current_.second;
    m.sender = 7;
    m.sender_name = "sim";
    return m;
  }
  int poll_fd() const override { return -1; }
  std::string describe() const override { return "fake:1"; }
  std::uint16_t port() const override { return 1; }

 private:
  std::pair<std::string, UtcNs> current_;
};

TEST(LockstepSocketSource, PosesArePlacedAtBasePlusSenderTimeWhateverTheirArrival) {
  auto socket = std::make_unique<ScriptedSocket>();
  auto* script = socket.get();
  sources::SocketSourceOptions options;
  options.sender_time_base = kT0;
  sources::SocketPoseSource source(std::move(socket), LocalFrame({43.0, -89.0, 260.0}), options);
  EXPECT_FALSE(source.sim_time());
  auto message = [&](const std::string& json, double arrival_s) {
    script->queue.emplace_back(json, parse_iso8601_utc("2030-01-01T00:00:00Z") + nanoseconds{std::llround(arrival_s * 1e9)});
  };
  // Sim time at half real speed: t advances 0.5 s per second of arrival.
  message(R"({"t": 0.0, "x": 0.0, "y": 0.0})", 0.0);
  message(R"({"t": 0.5, "x": 5.0, "y": 1.0})", 1.0);
  message(R"({"x": 9.0, "y": 9.0})", 1.5);  // no t: cannot be placed
  message(R"({"t": 1.0, "x": 10.0, "y": 2.0})", 2.0);
  source.service();
  EXPECT_EQ(source.stats().accepted, 3u);
  EXPECT_EQ(source.stats().rejected[static_cast<std::size_t>(sources::PoseReject::missing_key)], 1u);
  ASSERT_TRUE(source.sim_time());
  EXPECT_EQ(*source.sim_time(), at_s(1.0));
  const auto truth = source.truth_at(at_s(0.25));
  ASSERT_TRUE(truth);
  EXPECT_NEAR(truth->position_m.east_m, 2.5, 1e-9) << "interpolated in sim time";
  EXPECT_NEAR(truth->velocity_mps.east_m, 10.0, 1e-9) << "speed from sender times";
  const auto end = source.truth_at(at_s(1.0));
  ASSERT_TRUE(end);
  EXPECT_NEAR(end->position_m.east_m, 10.0, 1e-9);
}

// ---- end to end through the binary -------------------------------------------------------------

using test::udp_to;

double time_of_day_s(const std::string& hhmmss) {
  return std::stoi(hhmmss.substr(0, 2)) * 3600.0 + std::stoi(hhmmss.substr(2, 2)) * 60.0 + std::stod(hhmmss.substr(4));
}

TEST(LockstepEndToEnd, SimTimeAtHalfRealSpeedGivesEpochsThatFollowSimTimeExactlyNoneSkippedOrRepeated) {
  const LocalFrame frame({43.0725, -89.4125, 260.0});
  const int epochs = 10;  // 5 Hz: 2 s of sim time, 4 s of wall time
  test::Process gpsemu({GPSEMU_BINARY, "--clock", "lockstep", "--source", "udp:127.0.0.1:0", "--rate", "5",
                        "--start-time", "2024-05-01T12:00:00Z", "--duration", fmt::format("{}", epochs / 5.0),
                        "--noise", "none", "--sentences", "GGA", "--output", "stdout", "--pose-timeout", "1"});
  const auto port = test::wait_for_port(gpsemu, "waiting for poses on", seconds(20));
  ASSERT_TRUE(port) << gpsemu.stderr_text();
  const int fd = udp_to(*port);
  ASSERT_GE(fd, 0);
  // Sim time t = 0, 0.01, 0.02 ... sent every 20 ms of wall time: half real speed. The vehicle
  // drives east at 1 m/s of sim time: x = t.
  std::map<double, double> sent_wall_of_sim;  // sim t -> wall time it was sent
  const double start = test::realtime_now_s();
  int i = 0;
  while (test::realtime_now_s() - start < 15.0) {
    const double due = start + 0.02 * i;
    const double now = test::realtime_now_s();
    if (now >= due) {
      const double t = 0.01 * i;
      const std::string m = fmt::format(R"({{"t": {:.2f}, "x": {:.2f}, "y": 0.0}})", t, t);
      (void)::send(fd, m.data(), m.size(), MSG_DONTWAIT);
      sent_wall_of_sim[t] = now;
      ++i;
      continue;
    }
    if (!gpsemu.pump(milliseconds(static_cast<int>(std::ceil((due - now) * 1000.0))))) break;  // it exited
  }
  ::close(fd);
  ASSERT_EQ(gpsemu.wait(seconds(10)), 0) << gpsemu.stderr_text();

  // Every GGA, with the wall time its chunk was read.
  std::vector<std::pair<std::string, double>> ggas;
  for (const auto& c : gpsemu.chunks()) {
    for (std::size_t at = c.bytes.find("$GNGGA,"); at != std::string::npos; at = c.bytes.find("$GNGGA,", at + 1)) {
      ggas.emplace_back(c.bytes.substr(at, c.bytes.find('\n', at) - at), c.read_s);
    }
  }
  ASSERT_EQ(ggas.size(), static_cast<std::size_t>(epochs)) << gpsemu.stdout_text() << gpsemu.stderr_text();
  double worst_gap_error_ms = 0.0;
  for (int k = 0; k < epochs; ++k) {
    const std::string& gga = ggas[static_cast<std::size_t>(k)].first;
    const double sim_t = 0.2 * k;
    EXPECT_NEAR(time_of_day_s(gga.substr(7, 9)), 12 * 3600.0 + sim_t, 1e-6) << "epoch " << k << ": " << gga;
    // The reported position is the truth at sim time t: x = t metres east of the origin.
    const auto f = [&](int n) {
      std::size_t p = 0;
      for (int j = 0; j < n; ++j) p = gga.find(',', p) + 1;
      return gga.substr(p, gga.find(',', p) - p);
    };
    const double lon = -(std::stod(f(4).substr(0, 3)) + std::stod(f(4).substr(3)) / 60.0);
    const double lat = std::stod(f(2).substr(0, 2)) + std::stod(f(2).substr(2)) / 60.0;
    EXPECT_NEAR(frame.to_enu({lat, lon, 260.0}).east_m, sim_t, 0.02) << gga;
    // It left after the pose that reached its sim time was sent (not before).
    const auto reached = sent_wall_of_sim.lower_bound(sim_t - 1e-9);
    ASSERT_NE(reached, sent_wall_of_sim.end());
    EXPECT_GE(ggas[static_cast<std::size_t>(k)].second, reached->second) << "epoch " << k << " left early";
    if (k > 0) {
      const double gap_ms = 1000.0 * (ggas[static_cast<std::size_t>(k)].second - ggas[static_cast<std::size_t>(k - 1)].second);
      worst_gap_error_ms = std::max(worst_gap_error_ms, std::abs(gap_ms - 400.0));
    }
  }
  // Half real speed at 5 Hz: 400 ms of wall time between epochs (a generous bound: shared machine).
  EXPECT_LT(worst_gap_error_ms, 60.0);
  ::testing::Test::RecordProperty("worst_wall_spacing_error_ms", fmt::format("{:.2f}", worst_gap_error_ms));
  std::printf("[ info ] lockstep at half speed: %d epochs, wall spacing within %.2f ms of 400 ms\n", epochs,
              worst_gap_error_ms);
}

TEST(LockstepEndToEnd, NeedsASocketSourceAndRefusesFastAndPps) {
  test::Process sim({GPSEMU_BINARY, "--clock", "lockstep", "--output", "stdout", "--duration", "1"});
  EXPECT_EQ(sim.wait(seconds(20)), 2);
  EXPECT_NE(sim.stderr_text().find("--clock lockstep follows a simulator's time stamps: it needs a udp: or tcp: source"),
            std::string::npos) << sim.stderr_text();
  test::Process fast({GPSEMU_BINARY, "--clock", "lockstep", "--fast", "--source", "udp:0"});
  EXPECT_EQ(fast.wait(seconds(20)), 2);
  EXPECT_NE(fast.stderr_text().find("--fast and --clock lockstep"), std::string::npos) << fast.stderr_text();
  test::Process bad({GPSEMU_BINARY, "--clock", "stepwise"});
  EXPECT_EQ(bad.wait(seconds(20)), 2);
  EXPECT_NE(bad.stderr_text().find("unknown clock 'stepwise' (accepted: realtime, scaled:K, fast, lockstep)"),
            std::string::npos) << bad.stderr_text();
}

}  // namespace clock_lockstep_test
}  // namespace
}  // namespace gpsemu
