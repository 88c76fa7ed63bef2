// gpsemu-timing against a real gpsemu: three UDP outputs read by one tool process ({B+i} template,
// --count 3) and a pty read by another; the tool must count exactly the epochs gpsemu wrote (the
// file output beside them is the reference), with none missing or repeated. No timing thresholds:
// the deviations it measures are printed, not asserted.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/nmea_check.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace timing_tool_test {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

/// A base port B with B, B+1, ..., B+n-1 all free for UDP on 127.0.0.1 right now.
int free_udp_ports(int n) {
  std::mt19937 rng(static_cast<unsigned>(::getpid()));
  for (int attempt = 0; attempt < 200; ++attempt) {
    const int base = 20000 + static_cast<int>(rng() % 30000);
    bool ok = true;
    std::vector<int> fds;
    for (int i = 0; i < n && ok; ++i) {
      const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
      sockaddr_in a{};
      a.sin_family = AF_INET;
      a.sin_port = htons(static_cast<std::uint16_t>(base + i));
      a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      ok = ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
      fds.push_back(fd);
    }
    for (const int fd : fds) ::close(fd);
    if (ok) return base;
  }
  return -1;
}

using test::read_file;

/// The epoch times (RMC time field, seconds of the day) in an NMEA file, in order.
std::vector<double> epoch_times(const std::string& nmea) {
  std::vector<double> times;
  for (const auto& s : test::split_sentences(nmea).sentences) {
    if (test::sentence_type(s) != "RMC") continue;
    const std::string t = test::time_field(s);
    times.push_back(std::stoi(t.substr(0, 2)) * 3600.0 + std::stoi(t.substr(2, 2)) * 60.0 + std::stod(t.substr(4)));
  }
  return times;
}

class TimingToolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_root() / ("gpsemu-timing-test-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(TimingToolTest, CountsEveryEpochOfThreeUdpOutputsAndAPty) {
  const int base = free_udp_ports(3);
  ASSERT_GT(base, 0);
  const fs::path udp_json = dir_ / "udp.json", pty_json = dir_ / "pty.json", file = dir_ / "epochs.nmea";
  const fs::path link = dir_ / "gps";
  // The UDP reader binds before gpsemu starts, so it sees every datagram; it stops 1.5 s after
  // the last one.
  test::Process udp_tool({GPSEMU_TIMING_BINARY, "--udp", "127.0.0.1:{" + std::to_string(base) + "+i}", "--count", "3", "--latency", "0.05",
                          "--duration", "30", "--idle", "1.5", "--json", udp_json.string()});
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--duration", "3", "--latency", "0.05", "--log-level", "info",
                        "--output", "udp:127.0.0.1:" + std::to_string(base), "--output",
                        "udp:127.0.0.1:" + std::to_string(base + 1), "--output",
                        "udp:127.0.0.1:" + std::to_string(base + 2), "--output", "pty:" + link.string(), "--output",
                        "file:" + file.string()});
  ASSERT_TRUE(gpsemu.wait_for_stderr("pty output: /dev/pts", 10s)) << gpsemu.stderr_text();
  // The pty reader ends when gpsemu exits and the pty goes away.
  test::Process pty_tool({GPSEMU_TIMING_BINARY, "--device", link.string(), "--latency", "0.05", "--duration", "30",
                          "--json", pty_json.string()});
  ASSERT_EQ(gpsemu.wait(30s), 0) << gpsemu.stderr_text();
  const int udp_status = udp_tool.wait(30s);
  const int pty_status = pty_tool.wait(30s);
  ASSERT_EQ(udp_status, 0) << udp_tool.stdout_text() << udp_tool.stderr_text();
  ASSERT_EQ(pty_status, 0) << pty_tool.stdout_text() << pty_tool.stderr_text();
  std::printf("udp tool:\n%s\npty tool:\n%s\n", udp_tool.stdout_text().c_str(), pty_tool.stdout_text().c_str());

  // The reference: every epoch gpsemu wrote, from its file output.
  const std::vector<double> written = epoch_times(read_file(file));
  ASSERT_EQ(written.size(), 30u) << gpsemu.stderr_text();  // 3 s at 10 Hz
  std::smatch m;
  const std::string err = gpsemu.stderr_text();
  ASSERT_TRUE(std::regex_search(err, m, std::regex("([0-9]+) epochs emitted"))) << err;
  ASSERT_EQ(std::stoul(m[1]), written.size());

  const auto udp = nlohmann::json::parse(read_file(udp_json));
  EXPECT_EQ(udp["outputs"], 3);
  EXPECT_EQ(udp["silent_outputs"], 0);
  EXPECT_EQ(udp["total"]["epochs"], 3 * written.size());
  EXPECT_EQ(udp["total"]["missing"], 0);
  EXPECT_EQ(udp["total"]["repeated"], 0);
  EXPECT_NE(udp["clock"].get<std::string>().find("SO_TIMESTAMPNS"), std::string::npos);
  std::set<std::string> names;
  for (const auto& o : udp["per_output"]) {
    names.insert(o["name"].get<std::string>());
    EXPECT_EQ(o["epochs"], written.size()) << o["name"];
    EXPECT_EQ(o["missing"], 0) << o["name"];
    EXPECT_EQ(o["repeated"], 0) << o["name"];
    EXPECT_DOUBLE_EQ(o["first_epoch_s"].get<double>(), written.front()) << o["name"];
    EXPECT_DOUBLE_EQ(o["last_epoch_s"].get<double>(), written.back()) << o["name"];
    EXPECT_TRUE(std::isfinite(o["p99_ms"].get<double>()));
  }
  EXPECT_EQ(names, (std::set<std::string>{"udp:127.0.0.1:" + std::to_string(base),
                                          "udp:127.0.0.1:" + std::to_string(base + 1),
                                          "udp:127.0.0.1:" + std::to_string(base + 2)}));

  // The pty reader opened the link after gpsemu started and does not count its first epoch: it
  // must count every epoch gpsemu wrote from its first counted one to its last.
  const auto pty = nlohmann::json::parse(read_file(pty_json));
  ASSERT_EQ(pty["per_output"].size(), 1u);
  const auto& p = pty["per_output"][0];
  EXPECT_EQ(p["missing"], 0);
  EXPECT_EQ(p["repeated"], 0);
  ASSERT_FALSE(p["first_epoch_s"].is_null());
  const double first = p["first_epoch_s"], last = p["last_epoch_s"];
  std::size_t expected = 0;
  for (const double t : written) expected += t >= first - 1e-6 && t <= last + 1e-6 ? 1 : 0;
  EXPECT_EQ(p["epochs"], expected);
  EXPECT_GE(expected, written.size() / 2) << "the pty reader started late";
  EXPECT_NE(pty["clock"].get<std::string>().find("user space"), std::string::npos);
}

TEST_F(TimingToolTest, RealTimeOptionsAreAppliedOrRefusedWithAMessage) {
  // Applied (or, where not permitted, said so) before measuring: one line each on stderr.
  const auto r = test::run({GPSEMU_TIMING_BINARY, "--udp", "127.0.0.1:0", "--duration", "0.2", "--realtime-priority",
                            "10", "--lock-memory", "--timer-slack", "1"});
  EXPECT_TRUE(r.err.find("real-time priority SCHED_FIFO 10") != std::string::npos ||
              r.err.find("SCHED_FIFO 10 not set") != std::string::npos ||
              r.err.find("not permitted") != std::string::npos)
      << r.err;
  EXPECT_TRUE(r.err.find("memory locked") != std::string::npos || r.err.find("memory not locked") != std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("timer slack"), std::string::npos) << r.err;
  const auto bad = test::run({GPSEMU_TIMING_BINARY, "--udp", "127.0.0.1:0", "--duration", "1", "--realtime-priority", "100"});
  EXPECT_EQ(bad.status, 2) << bad.err;
  EXPECT_NE(bad.err.find("--realtime-priority"), std::string::npos) << bad.err;
}

TEST_F(TimingToolTest, RefusesACountWithoutATemplate) {
  const auto r = test::run({GPSEMU_TIMING_BINARY, "--udp", "127.0.0.1:7000", "--count", "3", "--duration", "1"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("needs {i} or {B+i}"), std::string::npos) << r.err;
}

}  // namespace timing_tool_test
}  // namespace
}  // namespace gpsemu
