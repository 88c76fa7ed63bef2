// Many receivers in one process, run end to end: every receiver is the receiver it would be alone
// (its output byte-identical to a one-receiver run with its seed and origin), each gets every epoch
// once, in order, on its own real UDP socket in real time (with the second writer thread), never
// before the epoch's time + latency, and with --clock lockstep the epochs follow the slowest
// simulator. Outputs and counts, not timings: the timing figures come from tools/measure-fleet.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "emulator/config/config.hpp"
#include "emulator/pipeline/runner.hpp"
#include "tests/support/nmea_check.hpp"
#include "tests/support/udp_socket.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace fleet_test {

using namespace std::chrono_literals;
using test::seconds_of_day;
namespace fs = std::filesystem;

fs::path scratch_dir(const std::string& name) { return test::scratch_dir("fleet", name); }
using test::read_file;
using test::udp_to;

/// Field n (0 = "$GNGGA") of an NMEA sentence.
std::string field(const std::string& sentence, int n) {
  std::size_t p = 0;
  for (int j = 0; j < n; ++j) p = sentence.find(',', p) + 1;
  return sentence.substr(p, sentence.find_first_of(",*", p) - p);
}

std::vector<std::string> ggas_in(const std::string& text) {
  std::vector<std::string> out;
  for (std::size_t at = text.find("GGA,"); at != std::string::npos; at = text.find("GGA,", at + 1)) {
    if (at >= 3 && text[at - 3] == '$') out.push_back(text.substr(at - 3, text.find('\n', at) - (at - 3)));
  }
  return out;
}

int run_in_process(const Config& config, RunStats* stats = nullptr, std::vector<ReceiverStats>* receivers = nullptr) {
  Runner runner(config);
  std::atomic<bool> stop{false};
  const int rc = runner.run(stop);
  if (stats) *stats = runner.stats();
  if (receivers) {
    for (std::size_t i = 0; i < runner.receivers(); ++i) receivers->push_back(runner.receiver_stats(i));
  }
  return rc;
}

TEST(FleetEndToEnd, EachReceiverWritesWhatItWouldWriteAlone) {
  const fs::path dir = scratch_dir("alone");
  // Three receivers: two from the shared settings (seed 11 + i), one table with its own origin,
  // source and seed. Every sentence, cgrw noise, a moving vehicle.
  const std::string toml = fmt::format(R"(
start-time = "2024-02-28T23:59:50Z"
rate = 10
duration = 30
fast = true
noise = "cgrw"
seed = 11
source = "sim:circle"
sentences = "GGA,RMC,GSA,GSV,VTG,ZDA,GLL,GST"
log-level = "warn"

[[receiver]]
output = "file:{0}/fleet0.nmea"

[[receiver]]
output = "file:{0}/fleet1.nmea"

[[receiver]]
output = "file:{0}/fleet2.nmea"
origin = "-33.8688,151.2093,58"
source = "sim:line"
seed = 99
)",
                                       dir.string());
  RunStats stats;
  std::vector<ReceiverStats> receivers;
  ASSERT_EQ(run_in_process(build_config_from_text(toml, "fleet.toml", {}), &stats, &receivers), 0);
  ASSERT_EQ(receivers.size(), 3u);
  EXPECT_EQ(stats.epochs_emitted, 300u);
  for (const auto& r : receivers) EXPECT_EQ(r.epochs_emitted, 300u);

  // Each alone, with the settings the fleet gave it.
  const std::vector<RawOptions> alone = {
      {{"seed", {"11"}}, {"source", {"sim:circle"}}},
      {{"seed", {"12"}}, {"source", {"sim:circle"}}},
      {{"seed", {"99"}}, {"source", {"sim:line"}}, {"origin", {"-33.8688,151.2093,58"}}},
  };
  for (std::size_t i = 0; i < alone.size(); ++i) {
    RawOptions options = alone[i];
    options.push_back({"start-time", {"2024-02-28T23:59:50Z"}});
    options.push_back({"rate", {"10"}});
    options.push_back({"duration", {"30"}});
    options.push_back({"fast", {"true"}});
    options.push_back({"noise", {"cgrw"}});
    options.push_back({"sentences", {"GGA,RMC,GSA,GSV,VTG,ZDA,GLL,GST"}});
    options.push_back({"log-level", {"warn"}});
    options.push_back({"output", {fmt::format("file:{}/alone{}.nmea", dir.string(), i)}});
    ASSERT_EQ(run_in_process(build_config(std::nullopt, options)), 0);
    const std::string fleet = read_file(dir / fmt::format("fleet{}.nmea", i));
    EXPECT_EQ(ggas_in(fleet).size(), 300u) << "receiver " << i;
    EXPECT_EQ(fleet, read_file(dir / fmt::format("alone{}.nmea", i))) << "receiver " << i << " differs from its run alone";
  }
  // Independent receivers: their positions differ (own seed; own origin for the third).
  const auto gga0 = ggas_in(read_file(dir / "fleet0.nmea"));
  const auto gga1 = ggas_in(read_file(dir / "fleet1.nmea"));
  const auto gga2 = ggas_in(read_file(dir / "fleet2.nmea"));
  int same_position = 0;
  for (std::size_t k = 0; k < gga0.size(); ++k) {
    EXPECT_EQ(field(gga0[k], 1), field(gga1[k], 1));  // one timeline: the same time in every receiver
    EXPECT_EQ(field(gga0[k], 1), field(gga2[k], 1));
    if (field(gga0[k], 2) == field(gga1[k], 2) && field(gga0[k], 4) == field(gga1[k], 4)) ++same_position;
    EXPECT_EQ(field(gga2[k], 3), "S") << gga2[k];
  }
  EXPECT_LT(same_position, 30) << "receivers 0 and 1 have the same noise";
  fs::remove_all(dir);
}

/// A UDP socket on loopback, port chosen by the kernel.
struct UdpSink : test::LoopbackUdpSocket {
  UdpSink() : LoopbackUdpSocket(SO_RCVBUF, 1 << 20) {}
  /// Datagrams until `count` came or `timeout` passed, each with its wall-clock read time.
  std::vector<std::pair<std::string, double>> read(std::size_t count, std::chrono::milliseconds timeout) {
    std::vector<std::pair<std::string, double>> got;
    if (count == 0) return got;
    (void)test::read_with_deadline(fd, test::ReadLimits(timeout), [&](std::string_view chunk) {
      got.emplace_back(std::string(chunk), test::realtime_now_s());
      return got.size() >= count;
    });
    return got;
  }
};

TEST(FleetEndToEnd, InRealTimeEveryReceiverGetsEveryEpochOnceInOrderAndNoneEarly) {
  // 12 receivers (a second writer thread from 8 on), 10 Hz for 2 s, each on its own UDP port.
  constexpr int kReceivers = 12;
  std::vector<std::unique_ptr<UdpSink>> sinks;
  std::string toml = "rate = 10\nduration = 2\nlatency = 0.05\nnoise = \"cgrw\"\nseed = 5\nsentences = \"GGA,RMC\"\n"
                     "log-level = \"warn\"\n";
  for (int i = 0; i < kReceivers; ++i) sinks.push_back(std::make_unique<UdpSink>());
  toml += test::receivers_writing_to(sinks);
  Runner runner(build_config_from_text(toml, "fleet.toml", {}));
  std::atomic<bool> stop{false};
  ASSERT_EQ(runner.run(stop), 0);
  const auto emitted = runner.stats().epochs_emitted;
  EXPECT_EQ(emitted + runner.stats().epochs_late_skipped, 20u);
  EXPECT_GE(emitted, 15u);  // a loaded machine may skip a few: they are counted above

  std::vector<std::string> first_times;
  std::set<std::string> positions;
  for (int i = 0; i < kReceivers; ++i) {
    EXPECT_EQ(runner.receiver_stats(static_cast<std::size_t>(i)).epochs_emitted, emitted);
    EXPECT_EQ(runner.outputs(static_cast<std::size_t>(i)).front()->stats().epochs_written, emitted);
    // Everything is in the socket's buffer by now: read it all.
    const auto got = sinks[static_cast<std::size_t>(i)]->read(emitted + 1, 200ms);
    ASSERT_EQ(got.size(), emitted) << "receiver " << i;
    std::vector<std::string> times;
    for (const auto& [datagram, read_s] : got) {
      const auto gga = ggas_in(datagram);
      ASSERT_EQ(gga.size(), 1u) << datagram;
      ASSERT_NE(datagram.find("RMC,"), std::string::npos) << datagram;
      times.push_back(field(gga[0], 1));
      positions.insert(field(gga[0], 2) + field(gga[0], 4));
    }
    for (std::size_t k = 1; k < times.size(); ++k) {
      EXPECT_LT(seconds_of_day(times[k - 1]), seconds_of_day(times[k])) << "receiver " << i << ": out of order";
    }
    if (i == 0) first_times = times;
    EXPECT_EQ(times, first_times) << "receiver " << i << " is on another timeline";
  }
  EXPECT_GT(positions.size(), static_cast<std::size_t>(kReceivers)) << "receivers share their noise";
}

TEST(FleetEndToEnd, NoEpochLeavesBeforeItsTimePlusLatency) {
  // Computed ahead, written at the deadline: the kernel's receive time stamp of each datagram is
  // never earlier than the epoch's time + latency (an order check: lateness is not asserted).
  constexpr int kReceivers = 9;
  const auto sinks = test::stamped_sinks(kReceivers);
  std::string toml = "rate = 10\nduration = 1.5\nlatency = 0.08\nsentences = \"GGA\"\nlog-level = \"warn\"\n";
  toml += test::receivers_writing_to(sinks);
  Runner runner(build_config_from_text(toml, "fleet.toml", {}));
  std::atomic<bool> stop{false};
  ASSERT_EQ(runner.run(stop), 0);
  std::size_t checked = 0;
  for (const auto& sink : sinks) {
    for (const auto& d : sink->drain_stamped()) {
      ASSERT_TRUE(d.stamped) << "no kernel time stamp";
      const double epoch_of_day = seconds_of_day(field(d.bytes, 1));
      double early = (epoch_of_day + 0.08) - d.seconds_of_day;
      if (early > 43200) early -= 86400;  // across midnight
      EXPECT_LE(early, 0.0) << "sent " << early * 1000 << " ms before its time: " << d.bytes;
      ++checked;
    }
  }
  EXPECT_EQ(checked, runner.stats().epochs_emitted * kReceivers);
}

void send_pose(int fd, double t) {
  const std::string m = fmt::format(R"({{"t": {:.2f}, "x": {:.2f}, "y": 0.0}})", t, t);
  (void)::send(fd, m.data(), m.size(), 0);
}

TEST(FleetEndToEnd, LockstepFollowsTheSlowestSimulator) {
  // Two simulators, one far ahead of the other: epochs leave as the slower one reaches them, for
  // both receivers, every epoch once.
  UdpSink out0, out1;
  const fs::path dir = scratch_dir("lockstep");
  const fs::path file = dir / "fleet.toml";
  std::ofstream(file) << fmt::format(
      "[[receiver]]\nsource = \"udp:127.0.0.1:0\"\noutput = \"udp:127.0.0.1:{}\"\n"
      "[[receiver]]\nsource = \"udp:127.0.0.1:0\"\noutput = \"udp:127.0.0.1:{}\"\n",
      out0.port, out1.port);
  test::Process gpsemu({GPSEMU_BINARY, "--config", file.string(), "--clock", "lockstep", "--rate", "5", "--start-time",
                        "2024-05-01T12:00:00Z", "--duration", "1", "--noise", "none", "--sentences", "GGA",
                        "--pose-timeout", "5"});
  std::vector<int> sim;
  for (int i = 0; i < 2; ++i) {
    const auto port = test::wait_for_port(gpsemu, "waiting for poses on", 20s);
    ASSERT_TRUE(port) << gpsemu.stderr_text();
    sim.push_back(udp_to(*port));
    ASSERT_GE(sim.back(), 0);
  }
  // Simulator 0 runs ahead to t = 1.2 s; simulator 1 has not started: nothing leaves.
  for (int k = 0; k <= 24; ++k) send_pose(sim[0], 0.05 * k);
  EXPECT_TRUE(out0.read(1, 400ms).empty()) << "an epoch left before the slower simulator started";
  // Simulator 1 starts at t = 0: the first epoch leaves for both.
  send_pose(sim[1], 0.0);
  EXPECT_EQ(out0.read(1, 10s).size(), 1u);
  EXPECT_EQ(out1.read(1, 10s).size(), 1u);
  // It reaches t = 0.45: epochs 0.2 and 0.4, not 0.6.
  for (int k = 1; k <= 9; ++k) send_pose(sim[1], 0.05 * k);
  const auto a0 = out0.read(3, 2s);  // two come; waits for a third that must not
  const auto a1 = out1.read(3, 2s);
  ASSERT_EQ(a0.size(), 2u) << "receiver 0 did not wait for the slower simulator";
  ASSERT_EQ(a1.size(), 2u);
  EXPECT_EQ(field(a0[1].first, 1), "120000.40") << a0[1].first;
  EXPECT_EQ(field(a1[1].first, 1), "120000.40") << a1[1].first;
  // It reaches the end: the last two epochs, then the run ends.
  for (int k = 10; k <= 24; ++k) send_pose(sim[1], 0.05 * k);
  const auto b0 = out0.read(2, 10s);
  const auto b1 = out1.read(2, 10s);
  ASSERT_EQ(b0.size(), 2u);
  ASSERT_EQ(b1.size(), 2u);
  EXPECT_EQ(field(b0[1].first, 1), "120000.80") << b0[1].first;
  EXPECT_EQ(gpsemu.wait(10s), 0) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find("receiver 1: 5 epochs"), std::string::npos) << gpsemu.stderr_text();
  for (const int fd : sim) ::close(fd);
  fs::remove_all(dir);
}

TEST(FleetEndToEnd, TheBinaryRunsManyReceiversAndSummarisesEach) {
  const fs::path dir = scratch_dir("binary");
  test::Process gpsemu({GPSEMU_BINARY, "--receivers", "4", "--rate", "10", "--fast", "--duration", "10", "--seed", "3", "--output",
                        (dir / "gps{i}.nmea").string().insert(0, "file:"), "--output",
                        (dir / "copy{100+i}.nmea").string().insert(0, "file:")});
  ASSERT_EQ(gpsemu.wait(30s), 0) << gpsemu.stderr_text();
  const std::string log = gpsemu.stderr_text();
  EXPECT_NE(log.find("4 receivers; 10 Hz"), std::string::npos) << log;
  for (int i = 0; i < 4; ++i) {
    EXPECT_NE(log.find(fmt::format("receiver {}: 100 epochs (0 without fix)", i)), std::string::npos) << log;
    EXPECT_NE(log.find(fmt::format("receiver {}: source", i)), std::string::npos) << log;
    const std::string a = read_file(dir / fmt::format("gps{}.nmea", i));
    EXPECT_EQ(ggas_in(a).size(), 100u);
    EXPECT_EQ(a, read_file(dir / fmt::format("copy{}.nmea", 100 + i)));
  }
  fs::remove_all(dir);
}

}  // namespace fleet_test
}  // namespace
}  // namespace gpsemu
