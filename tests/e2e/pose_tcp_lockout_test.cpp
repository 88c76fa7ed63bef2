// End to end: the TCP pose input cannot be locked out (docs/pose-input.md, "TCP connections").
// The real gpsemu binary with --source tcp:, the NMEA read from its stdout, real TCP connections
// on loopback: idle connections and half-lines fill the slots, yet a real sender gets its fix
// (a newcomer takes the slot of a client idle for 1 s; a client without a complete line for 5 s
// is closed); 1000 connects and closes log a bounded number of lines; and 30 s of connections
// opened and dropped in random patterns beside a real sender never cost its fix for longer than
// the idle timeout.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <random>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "tests/support/process.hpp"

namespace gpsemu {
namespace {
namespace pose_tcp_lockout_test {

using namespace std::chrono;

constexpr double kIdleTimeoutS = 5.0;  ///< documented: a TCP pose client without a complete line is closed

/// A connection to the pose port. `wait`: a blocking connect (the sender); otherwise started and
/// left to the kernel (the hogs: loopback drops a SYN now and then under churn, and a blocking
/// connect would then stall the test for the 1 s retransmission).
int tcp_open(std::uint16_t port, bool wait = true) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | (wait ? 0 : SOCK_NONBLOCK), 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0 && (wait || errno != EINPROGRESS)) {
    ::close(fd);
    return -1;
  }
  return fd;
}

bool send_text(int fd, const std::string& text) {
  return fd >= 0 && ::send(fd, text.data(), text.size(), MSG_NOSIGNAL | MSG_DONTWAIT) ==
                        static_cast<ssize_t>(text.size());
}

/// A simulator as a real one behaves: one connection, a pose a tick, and on a failed send (the
/// server refused or closed it) a new connection on the next tick.
class PoseSender {
 public:
  explicit PoseSender(std::uint16_t port) : port_(port) {}
  ~PoseSender() { reconnect(false); }
  void tick() {
    if (fd_ < 0) fd_ = tcp_open(port_);
    if (!send_text(fd_, R"({"x": 3, "y": 4})" "\n")) reconnect(false);
  }
  /// Closes the connection; with `open`, opens a new one at once.
  void reconnect(bool open) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = open ? tcp_open(port_) : -1;
    ++connections_;
  }

 private:
  std::uint16_t port_;
  int fd_ = -1;
  int connections_ = 0;
};

/// Starts gpsemu on a free TCP port for `duration_s` of 10 Hz epochs; returns the port.
std::uint16_t start(test::Process& p) {
  const auto port = test::wait_for_port(p, "waiting for poses on");
  if (!port) ADD_FAILURE() << "gpsemu did not start:\n" << p.stderr_text();
  return port.value_or(0);
}

std::vector<std::string> gpsemu_args(double duration_s) {
  return {GPSEMU_BINARY, "--source", "tcp:127.0.0.1:0", "--noise", "none", "--rate", "10",
          "--duration", fmt::format("{}", duration_s), "--output", "stdout", "--log-level", "info"};
}

/// Whether each epoch (GGA line, in order) has a fix.
std::vector<bool> gga_fixes(const std::string& nmea) {
  std::vector<bool> out;
  static const std::regex gga(R"(\$G.GGA,[^,]*,[^,]*,[^,]*,[^,]*,[^,]*,([0-9]),)");
  for (auto it = std::sregex_iterator(nmea.begin(), nmea.end(), gga); it != std::sregex_iterator(); ++it) {
    out.push_back((*it)[1].str() != "0");
  }
  return out;
}

struct FixRuns {
  std::optional<std::size_t> first_fix;  ///< epoch index
  std::size_t longest_gap = 0;           ///< epochs without a fix after the first fix
  std::size_t fixes = 0;
};

FixRuns fix_runs(const std::vector<bool>& fixes) {
  FixRuns r;
  std::size_t gap = 0;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    if (fixes[i]) {
      ++r.fixes;
      if (!r.first_fix) r.first_fix = i;
      gap = 0;
    } else if (r.first_fix) {
      r.longest_gap = std::max(r.longest_gap, ++gap);
    }
  }
  return r;
}

/// Runs `step(i)` every 50 ms for `seconds`, reading gpsemu's output meanwhile.
void pace_20hz(test::Process& p, double seconds, const std::function<void(int)>& step) {
  const auto start = steady_clock::now();
  for (int i = 0; i < static_cast<int>(seconds * 20.0); ++i) {
    while (steady_clock::now() < start + milliseconds(50) * i) (void)p.pump(milliseconds(5));
    step(i);
  }
}

/// From the pose input's summary: "N what" (counts) or "what N" (refusals by reason, `reason`).
std::uint64_t summary_count(const std::string& err, const std::string& what, bool reason = false) {
  std::smatch m;
  if (!std::regex_search(err, m, std::regex(reason ? what + " ([0-9]+)" : "([0-9]+) " + what))) return 0;
  return std::stoull(m[1].str());
}

void close_all(std::vector<int>& fds) {
  for (const int fd : fds) ::close(fd);
  fds.clear();
}

/// `hog` fills the slots before the sender starts; the sender then sends for most of the run.
void expect_sender_gets_fix_beside(const std::function<void(std::uint16_t, std::vector<int>&)>& hog,
                                   std::vector<std::string>& err_out) {
  const double duration = 8.0;
  test::Process gpsemu(gpsemu_args(duration));
  const std::uint16_t port = start(gpsemu);
  ASSERT_GT(port, 0);
  std::vector<int> hogs;
  hog(port, hogs);
  PoseSender sender(port);
  pace_20hz(gpsemu, duration - 0.5, [&](int) { sender.tick(); });
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  close_all(hogs);
  const FixRuns runs = fix_runs(gga_fixes(gpsemu.stdout_text()));
  ASSERT_TRUE(runs.first_fix) << gpsemu.stderr_text();
  // The slots' holders are idle for the take-over time (1 s) at the latest 1 s after the sender
  // starts: it has its fix within about 2 s and keeps it.
  EXPECT_LE(*runs.first_fix, 30u) << gpsemu.stderr_text();
  EXPECT_EQ(runs.longest_gap, 0u) << gpsemu.stderr_text();
  EXPECT_GE(summary_count(gpsemu.stderr_text(), "taken over"), 1u) << gpsemu.stderr_text();
  err_out.push_back(gpsemu.stderr_text());
}

TEST(PoseTcpLockout, EightIdleConnectionsThenARealSenderGetsItsFix) {
  std::vector<std::string> err;
  expect_sender_gets_fix_beside(
      [](std::uint16_t port, std::vector<int>& fds) {
        for (int k = 0; k < 8; ++k) fds.push_back(tcp_open(port, false));
      },
      err);
  ASSERT_EQ(err.size(), 1u);
  // The holders the sender did not push out are closed after the idle timeout (5 s of the 8 s run).
  EXPECT_GE(summary_count(err[0], "closed idle"), 1u) << err[0];
}

TEST(PoseTcpLockout, FiveHundredHalfLinesThenARealSenderGetsItsFix) {
  std::vector<std::string> err;
  expect_sender_gets_fix_beside(
      [](std::uint16_t port, std::vector<int>& fds) {
        for (int k = 0; k < 500; ++k) fds.push_back(tcp_open(port, false));
        std::this_thread::sleep_for(milliseconds(50));
        for (const int fd : fds) (void)send_text(fd, R"({"x": 100, "y": )");  // those connected by now
      },
      err);
  ASSERT_EQ(err.size(), 1u);
  // 500 connections and their refusals are logged in a few rate-limited lines.
  std::size_t lines = 0;
  for (const char ch : err[0]) lines += ch == '\n';
  EXPECT_LE(lines, 80u) << err[0];
}

TEST(PoseTcpLockout, ChurnOfAThousandConnectsLogsABoundedNumberOfLines) {
  test::Process gpsemu(gpsemu_args(4.0));
  const std::uint16_t port = start(gpsemu);
  ASSERT_GT(port, 0);
  std::vector<int> batch;
  for (int k = 0; k < 1000; ++k) {  // in batches of 50: connect, then close them 20 ms later
    batch.push_back(tcp_open(port, false));
    ASSERT_GE(batch.back(), 0);
    if (batch.size() == 50) {
      (void)gpsemu.pump(milliseconds(20));
      close_all(batch);
    }
  }
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  const std::string err = gpsemu.stderr_text();
  std::size_t churn_lines = 0, lines = 0;
  for (std::size_t at = 0; (at = err.find('\n', at)) != std::string::npos; ++at) ++lines;
  for (std::size_t at = 0; (at = err.find("pose sender", at)) != std::string::npos; ++at) ++churn_lines;
  // At most one line a second per kind (connected, disconnected, refused): 4 s of run.
  EXPECT_LE(churn_lines, 3u * 5u) << err;
  EXPECT_LE(lines, 40u) << err;
  // The connections are counted (some of the 1000 were closed before their handshake was done).
  EXPECT_GE(summary_count(err, "connections") + summary_count(err, "too_many_clients", true), 200u) << err;
  EXPECT_LE(summary_count(err, "connections") + summary_count(err, "too_many_clients", true), 1000u) << err;
}

TEST(PoseTcpLockout, RandomConnectionsBesideARealSenderNeverCostTheFixLongerThanTheIdleTimeout) {
  const double duration = 18.0;  // three reconnections of the sender, ~700 random operations
  test::Process gpsemu(gpsemu_args(duration + 1.0));
  const std::uint16_t port = start(gpsemu);
  ASSERT_GT(port, 0);
  const unsigned seed = std::random_device{}();
  SCOPED_TRACE(fmt::format("seed {}", seed));
  std::mt19937 rng(seed);
  std::vector<int> held;
  PoseSender sender(port);
  std::vector<int> brief;  // opened on one tick, dropped on the next
  std::uint64_t opened = 0;
  pace_20hz(gpsemu, duration, [&](int i) {
    sender.tick();
    close_all(brief);
    if (i > 0 && i % 120 == 0) sender.reconnect(true);  // every 6 s: a new connection must get a slot
    for (int ops = std::uniform_int_distribution<int>(0, 3)(rng); ops > 0; --ops) {
      switch (std::uniform_int_distribution<int>(0, 6)(rng)) {
        case 0:  // an idle connection, held
          held.push_back(tcp_open(port, false));
          ++opened;
          break;
        case 1:  // a half-line (sent if connected by now), held
          held.push_back(tcp_open(port, false));
          (void)send_text(held.back(), R"({"x": 7, )");
          ++opened;
          break;
        case 2:  // open and drop
          brief.push_back(tcp_open(port, false));
          ++opened;
          break;
        case 3:  // a burst of idle connections
          for (int k = 0; k < 10; ++k) held.push_back(tcp_open(port, false));
          opened += 10;
          break;
        case 4:  // a junk line (if connected by now), then silence
          held.push_back(tcp_open(port, false));
          (void)send_text(held.back(), "{junk}\n");
          ++opened;
          break;
        default:  // drop some held ones
          for (int k = std::uniform_int_distribution<int>(1, 8)(rng); k > 0 && !held.empty(); --k) {
            const auto at = std::uniform_int_distribution<std::size_t>(0, held.size() - 1)(rng);
            ::close(held[at]);
            held.erase(held.begin() + static_cast<std::ptrdiff_t>(at));
          }
      }
    }
    while (held.size() > 200) {  // stay within the test's descriptors
      ::close(held.front());
      held.erase(held.begin());
    }
  });
  ASSERT_EQ(gpsemu.wait(seconds(30)), 0) << gpsemu.stderr_text();
  close_all(held);
  close_all(brief);
  const FixRuns runs = fix_runs(gga_fixes(gpsemu.stdout_text()));
  ASSERT_TRUE(runs.first_fix) << gpsemu.stderr_text();
  EXPECT_LE(*runs.first_fix, 10u * kIdleTimeoutS);
  EXPECT_LE(static_cast<double>(runs.longest_gap) / 10.0, kIdleTimeoutS)
      << "the sender's fix was lost for " << runs.longest_gap << " epochs\n" << gpsemu.stderr_text();
  EXPECT_GE(runs.fixes, static_cast<std::size_t>(10.0 * (duration - kIdleTimeoutS)));
  EXPECT_GE(opened, 100u);
}

}  // namespace pose_tcp_lockout_test
}  // namespace
}  // namespace gpsemu
