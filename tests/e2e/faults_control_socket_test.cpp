// The control socket as an operator meets it, through the binary: a second gpsemu on the same
// --control unix:PATH is refused (exit 2, naming the path) and leaves the first one reachable and
// its socket in place; idle clients are closed after --control-idle-timeout, so eight silent
// connections do not lock `gpsemu ctl` out; clients refused, closed idle and error answers are
// logged and counted in the exit summary.
// Each gpsemu runs in real time at 10 Hz (a receiver an operator controls; the pending fault is
// checked before the next epoch) only as long as the checks take: a SIGTERM ends it cleanly
// (exit 0, summary written), --duration is only a bound.
#include <gtest/gtest.h>
#include <signal.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace faults_control_socket_test {

using std::chrono::milliseconds;
using std::chrono::seconds;

/// A client connected to the Unix socket at `path` (-1: none).
int connect_unix(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, path.data(), path.size());
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

/// The first line `fd` receives within `timeout` ("" if none).
std::string read_line(int fd, milliseconds timeout) {
  std::string text;
  char c = 0;
  pollfd p{fd, POLLIN, 0};
  while (::poll(&p, 1, static_cast<int>(timeout.count())) > 0 && ::recv(fd, &c, 1, 0) == 1 && c != '\n') text += c;
  return text;
}

TEST(FaultsControlSocket, ASecondGpsemuOnALiveSocketIsRefusedAndTheFirstStaysReachable) {
  const auto dir = test::scratch_dir("faults", "control-taken");
  const std::string socket = (dir / "ctl.sock").string();
  test::Process first({GPSEMU_BINARY, "--rate", "10", "--duration", "60", "--output", "file:" + (dir / "a.nmea").string(),
                       "--control", "unix:" + socket});
  ASSERT_TRUE(first.wait_for_stderr("control socket", seconds(20))) << first.stderr_text();

  const test::Result second = test::run({GPSEMU_BINARY, "--fast", "--duration", "1", "--output",
                                         "file:" + (dir / "b.nmea").string(), "--control", "unix:" + socket},
                                        seconds(20));
  EXPECT_EQ(second.status, 2) << second.err;
  EXPECT_TRUE(test::contains(second.err, socket)) << second.err;
  EXPECT_TRUE(test::contains(second.err, "in use")) << second.err;

  EXPECT_TRUE(std::filesystem::exists(socket)) << "the second gpsemu removed the first one's socket";
  const test::Result status = test::run({GPSEMU_BINARY, "ctl", socket, "status"});
  EXPECT_EQ(status.status, 0) << status.out << status.err;
  EXPECT_TRUE(test::contains(status.out, R"("class":"STATUS")")) << status.out;

  first.signal(SIGTERM);
  ASSERT_EQ(first.wait(seconds(20)), 0) << first.stderr_text();
  EXPECT_FALSE(std::filesystem::exists(socket)) << "the first gpsemu left its socket behind";
  std::filesystem::remove_all(dir);
}

TEST(FaultsControlSocket, IdleClientsAreClosedSoCtlGetsInAndEveryDropIsCounted) {
  const auto dir = test::scratch_dir("faults", "control-idle");
  const std::string socket = (dir / "ctl.sock").string();
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--duration", "60", "--output", "file:" + (dir / "a.nmea").string(),
                        "--control", "unix:" + socket, "--control-idle-timeout", "0.5"});
  ASSERT_TRUE(gpsemu.wait_for_stderr("control socket", seconds(20))) << gpsemu.stderr_text();

  // Eight silent clients take every place; a ninth is refused.
  std::vector<int> idle;
  for (int i = 0; i < 8; ++i) idle.push_back(connect_unix(socket));
  const int ninth = connect_unix(socket);
  EXPECT_TRUE(test::contains(read_line(ninth, seconds(2)), "too many control clients"));
  ::close(ninth);

  // After the idle timeout they are told and closed, and ctl gets in.
  for (const int fd : idle) EXPECT_TRUE(test::contains(read_line(fd, seconds(3)), "no request for 0.5 s"));
  const test::Result status = test::run({GPSEMU_BINARY, "ctl", socket, "status"});
  EXPECT_EQ(status.status, 0) << status.out << status.err;
  const test::Result bad = test::run({GPSEMU_BINARY, "ctl", socket, "jam", "--db", "99"});
  EXPECT_EQ(bad.status, 1) << bad.out << bad.err;
  for (const int fd : idle) ::close(fd);

  gpsemu.signal(SIGTERM);
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  const std::string err = gpsemu.stderr_text();
  EXPECT_TRUE(test::contains(err, "1 client(s) refused (already 8 connected)")) << err;
  EXPECT_TRUE(test::contains(err, " closed idle (no request for 0.5 s)")) << err;
  EXPECT_FALSE(test::contains(err, "0 dropped (not reading")) << err;  // a drop line names only what happened
  EXPECT_TRUE(test::contains(err, "error answer to")) << err;
  EXPECT_TRUE(test::contains(err, "2 requests answered (1 errors, 0 refused before parsing); 10 clients connected, 1 refused "
                                  "(too many), 0 closed for a newcomer, 8 closed idle"))
      << err;
  std::filesystem::remove_all(dir);
}

TEST(FaultsControlSocket, CtlHasAFlagForEveryParameterAndItsHelpNamesPathAndKind) {
  const test::Result help = test::run({GPSEMU_BINARY, "ctl", "--help"});
  EXPECT_EQ(help.status, 0) << help.err;
  for (const char* text : {"PATH", "KIND", "spoof: --bearing-deg|--bearing", "latency: --delay-ms|--delay"})
    EXPECT_TRUE(test::contains(help.out, text)) << text << "\n" << help.out;

  const auto dir = test::scratch_dir("faults", "control-flags");
  const std::string socket = (dir / "ctl.sock").string();
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--duration", "60", "--output", "file:" + (dir / "a.nmea").string(),
                        "--control", "unix:" + socket});
  ASSERT_TRUE(gpsemu.wait_for_stderr("control socket", seconds(20))) << gpsemu.stderr_text();
  const test::Result spoof = test::run({GPSEMU_BINARY, "ctl", socket, "spoof", "--speed", "2", "--bearing", "45"});
  EXPECT_EQ(spoof.status, 0) << spoof.out << spoof.err;
  EXPECT_TRUE(test::contains(spoof.out, "spoof speed_mps=2 bearing_deg=45")) << spoof.out;
  const test::Result latency = test::run({GPSEMU_BINARY, "ctl", socket, "latency", "--delay=300", "--duration", "1"});
  EXPECT_EQ(latency.status, 0) << latency.out << latency.err;
  // Right after the answer, before the next epoch: status shows the latency as pending.
  const test::Result status = test::run({GPSEMU_BINARY, "ctl", socket, "status"});
  EXPECT_TRUE(test::contains(status.out, "latency")) << status.out;
  const test::Result extra = test::run({GPSEMU_BINARY, "ctl", socket, "status", "now"});
  EXPECT_EQ(extra.status, 2) << extra.out;
  EXPECT_TRUE(test::contains(extra.err, "unexpected word 'now'")) << extra.err;
  gpsemu.signal(SIGTERM);
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  std::filesystem::remove_all(dir);
}


/// The number in "N late epochs skipped" of a run's summary (-1: none).
int late_epochs_of(const std::string& log) {
  const std::string key = " late epochs skipped";
  const std::size_t at = log.find(key);
  if (at == std::string::npos) return -1;
  std::size_t begin = at;
  while (begin > 0 && std::isdigit(static_cast<unsigned char>(log[begin - 1]))) --begin;
  return std::stoi(log.substr(begin, at - begin));
}

TEST(FaultsControlSocket, EmptyLinesHoldNoSlotAndANewcomerTakesAQuietClientsPlace) {
  const auto dir = test::scratch_dir("faults", "control-empty-lines");
  const std::string socket = (dir / "ctl.sock").string();
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--duration", "60", "--output", "file:" + (dir / "a.nmea").string(),
                        "--control", "unix:" + socket});
  ASSERT_TRUE(gpsemu.wait_for_stderr("control socket", seconds(20))) << gpsemu.stderr_text();
  // Eight clients that send only "\n", every half second, for 3 s (the default idle timeout is 30 s).
  std::vector<int> holders;
  for (int i = 0; i < 8; ++i) holders.push_back(connect_unix(socket));
  for (int k = 0; k < 6; ++k) {
    for (const int fd : holders) (void)::send(fd, "\n", 1, MSG_NOSIGNAL);
    test::pump_for(gpsemu, milliseconds(500));
  }
  // The operator gets in every time (four tries), each taking the place of one of them.
  for (int k = 0; k < 4; ++k) {
    const test::Result status = test::run({GPSEMU_BINARY, "ctl", socket, "status"});
    EXPECT_EQ(status.status, 0) << status.out << status.err;
    EXPECT_TRUE(test::contains(status.out, R"("class":"STATUS")")) << status.out;
  }
  std::size_t told = 0;
  for (const int fd : holders) {
    if (test::contains(read_line(fd, milliseconds(200)), "every slot is taken")) ++told;
    ::close(fd);
  }
  EXPECT_EQ(told, 1u) << "the first ctl took a quiet client's place, the others the place it left";
  gpsemu.signal(SIGTERM);
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  const std::string err = gpsemu.stderr_text();
  EXPECT_TRUE(test::contains(err, "0 refused (too many), 1 closed for a newcomer")) << err;
  EXPECT_TRUE(test::contains(err, "48 empty lines skipped")) << err;
  std::filesystem::remove_all(dir);
}

TEST(FaultsControlSocket, AClientPipeliningRequestsMakesNoEpochLate) {
  const auto dir = test::scratch_dir("faults", "control-pipelining");
  const std::string socket = (dir / "ctl.sock").string();
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--duration", "60", "--output", "file:" + (dir / "a.nmea").string(),
                        "--control", "unix:" + socket});
  ASSERT_TRUE(gpsemu.wait_for_stderr("first epoch", seconds(20))) << gpsemu.stderr_text();
  const int fd = connect_unix(socket);
  ASSERT_GE(fd, 0);
  // For 4 s, status requests as fast as the socket takes them, every answer read.
  const std::string request = "{\"status\":true}\n";
  std::string burst;
  for (int k = 0; k < 64; ++k) burst += request;
  std::size_t sent = 0, answers = 0;
  const auto end = std::chrono::steady_clock::now() + seconds(4);
  char buffer[65536];
  while (std::chrono::steady_clock::now() < end) {
    pollfd p{fd, POLLIN | POLLOUT, 0};
    if (::poll(&p, 1, 20) <= 0) continue;
    if (p.revents & POLLOUT) {
      const ssize_t n = ::send(fd, burst.data(), burst.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n > 0) sent += static_cast<std::size_t>(n);
    }
    if (p.revents & POLLIN) {
      const ssize_t n = ::recv(fd, buffer, sizeof buffer, MSG_DONTWAIT);
      for (ssize_t k = 0; k < n; ++k) answers += buffer[k] == '\n';
    }
    gpsemu.pump(milliseconds(0));
  }
  ::close(fd);
  // Answered at its rate: 100 a second after a burst of 32 (4 s: about 430), the rest held in its socket.
  EXPECT_GT(answers, 300u) << "sent " << sent / request.size();
  EXPECT_LT(answers, 500u) << "sent " << sent / request.size();
  gpsemu.signal(SIGTERM);
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  const std::string err = gpsemu.stderr_text();
  EXPECT_GE(late_epochs_of(err), 0) << err;
  // (The first epoch alone may be skipped when an instrumented start-up outlasts its lead: ui_server_test.)
  EXPECT_LE(late_epochs_of(err), 1) << err.substr(err.size() > 3000 ? err.size() - 3000 : 0);
  EXPECT_FALSE(test::contains(err, "dropped (not reading")) << err.substr(err.size() > 3000 ? err.size() - 3000 : 0);
  EXPECT_TRUE(test::contains(err, "held to 100 requests a second 1 times")) << err.substr(err.size() > 3000 ? err.size() - 3000 : 0);
}

TEST(FaultsControlSocket, ATcpBindOffLoopbackIsRefusedAtStart) {
  for (const std::string bind : {"tcp:0.0.0.0:0", "tcp:[::]:0"}) {
    const test::Result r = test::run({GPSEMU_BINARY, "--fast", "--duration", "1", "--control", bind}, seconds(20));
    EXPECT_EQ(r.status, 2) << bind << ": " << r.err;
    EXPECT_TRUE(test::contains(r.err, "no token")) << r.err;
  }
  const test::Result ok = test::run({GPSEMU_BINARY, "--fast", "--duration", "1", "--output", "file:/dev/null", "--control",
                                     "tcp:127.0.0.1:0"}, seconds(20));
  EXPECT_EQ(ok.status, 0) << ok.err;
}

}  // namespace faults_control_socket_test
}  // namespace
}  // namespace gpsemu
