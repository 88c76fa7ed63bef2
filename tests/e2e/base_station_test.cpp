// `gpsemu base` end to end: the simulated base station's RTCM3 takes a second gpsemu, an F9P rover,
// to RTK fixed with no other software, over UDP (`gpsemu base --output udp:...` into the rover's
// `--rtcm udp:PORT`) and over a socat pty pair (the base on one end of the cable, the rover's u-blox
// port on the other, as an autopilot forwards a ground station's RTCM3 into the receiver's port):
// GGA quality 4 and NAV-PVT carrSoln 2. Its output is decoded by RTKLIB's convbin (observations of
// each system, one epoch a second, ranges a satellite can have) and gpsd's gpsdecode (the message
// types of each epoch); a TCP server output serves several clients at once; bad options exit 2
// with one line naming the option. Both gpsemu run on scaled clocks (x5): a few seconds each.
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "emulator/rtk/rtcm3_reader.hpp"
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/socat_pair.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu {
namespace {
namespace base_station_test {

namespace fs = std::filesystem;
using namespace std::chrono;

/// GGA quality of every epoch in `bytes`, in order.
std::vector<int> gga_qualities(const std::string& bytes) {
  std::vector<int> out;
  nmea::StreamReader reader;
  for (const auto& s : reader.feed(bytes)) {
    if (s.type != "GGA") continue;
    const auto gga = nmea::parse_gga(s);
    if (gga.ok()) out.push_back(static_cast<int>(gga->quality));
  }
  return out;
}

/// NAV-PVT carrSoln (0 none, 1 float, 2 fixed) of every NAV-PVT in `bytes`.
std::vector<int> carrier_solutions(const std::string& bytes) {
  std::vector<int> out;
  for (const ubx::Frame& f : ubx::test::frames_in(bytes)) {
    if (f.id == ubx::msg::nav_pvt && f.payload.size() == 92) out.push_back(ubx::get_u1(f.payload, 21) >> 6);
  }
  return out;
}

/// Stops a base that runs until stopped and returns its exit status.
int stop(test::Process& base) {
  base.signal(SIGTERM);
  return base.wait(seconds(20));
}

TEST(BaseStation, OverUdpAnF9pRoverReachesRtkFixed) {
  const fs::path dir = test::scratch_dir("base", "udp");
  const fs::path nmea = dir / "rover.nmea";
  test::Process rover({GPSEMU_BINARY, "--receiver", "ublox-f9p", "--rtcm", "udp:0", "--clock", "scaled:5", "--duration",
                       "30", "--output", "file:" + nmea.string(), "--log-level", "info"});
  const auto port = test::wait_for_port(rover, "reading RTCM3 corrections on");
  ASSERT_TRUE(port) << rover.stderr_text();
  test::Process base({GPSEMU_BINARY, "base", "--output", fmt::format("udp:127.0.0.1:{}", *port), "--clock", "scaled:5"});
  ASSERT_EQ(rover.wait(seconds(60)), 0) << rover.stderr_text();
  EXPECT_EQ(stop(base), 0) << base.stderr_text();

  const std::vector<int> q = gga_qualities(test::read_file(nmea));
  ASSERT_EQ(q.size(), 30u) << rover.stderr_text();
  // DGPS at the first MSM, then float, then fixed (10 s after the first MSM at a zero baseline),
  // and fixed at the end.
  const auto dgps = std::find(q.begin(), q.end(), 2);
  const auto rtk_float = std::find(dgps, q.end(), 5);
  const auto fixed = std::find(rtk_float, q.end(), 4);
  EXPECT_NE(fixed, q.end()) << ::testing::PrintToString(q) << "\n" << rover.stderr_text();
  EXPECT_EQ(q.back(), 4) << ::testing::PrintToString(q);
  EXPECT_GE(std::count(q.begin(), q.end(), 4), 10) << ::testing::PrintToString(q);
  const std::string& log = rover.stderr_text();
  EXPECT_TRUE(test::contains(log, "RTK: RTK fixed")) << log;
  for (const char* type : {"1005 x", "1074 x", "1084 x", "1230 x"}) {
    EXPECT_TRUE(test::contains(log, type)) << type << "\n" << log;
  }
  EXPECT_TRUE(test::contains(log, "0 bad CRC dropped, 0 too short")) << log;
  // The base's summary: epochs, messages by type, bytes, per output.
  EXPECT_TRUE(std::regex_search(base.stderr_text(), std::regex(R"(base: \d+ epochs, \d+ RTCM3 messages \(1005 x\d+, 1074 x)")))
      << base.stderr_text();
  EXPECT_TRUE(test::contains(base.stderr_text(), fmt::format("udp:127.0.0.1:{}: ", *port))) << base.stderr_text();
  fs::remove_all(dir);
}

TEST(BaseStation, OverAPtyPairIntoTheRoversPortItReachesRtkFixed) {
  const fs::path dir = test::scratch_dir("base", "pty");
  const fs::path out = dir / "rover.bin";
  test::SocatPair cable(dir / "base", dir / "rover");
  // The rover's u-blox port is its end of the cable: what the base writes arrives as client input.
  test::Process rover({GPSEMU_BINARY, "--receiver", "ublox-f9p", "--protocol", "nmea+ubx", "--output",
                       "serial:" + cable.b().string() + "@115200", "--output", "file:" + out.string(), "--clock",
                       "scaled:5", "--duration", "30", "--log-level", "info"});
  ASSERT_TRUE(rover.wait_for_stderr("scaled clock", seconds(20))) << rover.stderr_text();
  test::Process base({GPSEMU_BINARY, "base", "--output", "serial:" + cable.a().string() + "@115200", "--clock", "scaled:5",
                      "--msm", "7", "--antenna-height", "1.5"});
  ASSERT_EQ(rover.wait(seconds(60)), 0) << rover.stderr_text();
  EXPECT_EQ(stop(base), 0) << base.stderr_text();

  const std::string bytes = test::read_file(out);
  const std::vector<int> q = gga_qualities(bytes), carr = carrier_solutions(bytes);
  ASSERT_FALSE(q.empty()) << rover.stderr_text();
  ASSERT_FALSE(carr.empty()) << rover.stderr_text();
  EXPECT_GE(std::count(q.begin(), q.end(), 4), 10) << ::testing::PrintToString(q) << "\n" << rover.stderr_text();
  EXPECT_EQ(q.back(), 4) << ::testing::PrintToString(q);
  EXPECT_GE(std::count(carr.begin(), carr.end(), 2), 10) << ::testing::PrintToString(carr);
  EXPECT_EQ(carr.back(), 2) << ::testing::PrintToString(carr);
  const std::string& log = rover.stderr_text();
  EXPECT_TRUE(test::contains(log, "first RTCM3 1006 base position")) << log;
  EXPECT_TRUE(test::contains(log, "first RTCM3 1077 GPS MSM7")) << log;
  EXPECT_TRUE(test::contains(log, "RTCM3 frames (0 bad CRC)")) << log;  // the port's client-input line
  fs::remove_all(dir);
}

TEST(BaseStation, ATcpServerOutputServesSeveralClients) {
  test::Process base({GPSEMU_BINARY, "base", "--output", "tcp:0", "--clock", "scaled:10", "--systems", "GPS"});
  const auto port = test::wait_for_port(base, "listening on tcp:");
  ASSERT_TRUE(port) << base.stderr_text();
  std::vector<int> clients;
  for (int i = 0; i < 3; ++i) {
    const int fd = test::connect_to_loopback(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0), *port);
    ASSERT_GE(fd, 0) << "cannot connect to the base's port " << *port;
    clients.push_back(fd);
  }
  // Every client gets whole epochs: at least three each (1005, GPS MSM4, 1230), within 10 s.
  std::vector<std::string> got(clients.size());
  // Counted as whole decoded frames: a payload can hold the preamble byte 0xD3 too (more so with
  // more satellites in the MSM), so counting that byte could stop before the third epoch is whole.
  const auto three_epochs = [](const std::string& bytes) { return rtk::Rtcm3Reader().feed(bytes).size() >= 9; };
  for (const auto until = steady_clock::now() + seconds(10); steady_clock::now() < until;) {
    base.pump(milliseconds(50));
    for (std::size_t i = 0; i < clients.size(); ++i) {
      char buf[4096];
      ssize_t n;
      while ((n = ::recv(clients[i], buf, sizeof buf, MSG_DONTWAIT)) > 0) got[i].append(buf, static_cast<std::size_t>(n));
    }
    if (std::all_of(got.begin(), got.end(), three_epochs)) break;
  }
  for (std::size_t i = 0; i < clients.size(); ++i) {
    rtk::Rtcm3Reader reader;
    std::vector<int> types;
    for (const rtk::Rtcm3Frame& f : reader.feed(got[i])) types.push_back(f.message_type());
    ASSERT_GE(types.size(), 9u) << "client " << i << "\n" << base.stderr_text();
    EXPECT_EQ(reader.stats().bad_crc, 0u);
    EXPECT_EQ(reader.stats().garbage_bytes, 0u);  // whole frames from the first byte
    EXPECT_EQ(std::count(types.begin(), types.end(), 1074), std::count(types.begin(), types.end(), 1005));
    for (const int t : types) EXPECT_TRUE(t == 1005 || t == 1074 || t == 1230) << t;
    ::close(clients[i]);
  }
  EXPECT_EQ(stop(base), 0) << base.stderr_text();
}

TEST(BaseStation, ClientsThatNeverReadDoNotKeepARealReaderOut) {
  // 300 connections that never read (32 slots); a real reader arriving 2.5 s later is served.
  test::Process base({GPSEMU_BINARY, "base", "--output", "tcp:0", "--systems", "GPS"});
  const auto port = test::wait_for_port(base, "listening on tcp:");
  ASSERT_TRUE(port) << base.stderr_text();
  std::vector<int> idle;
  for (int i = 0; i < 300; ++i) {
    const int fd = test::connect_to_loopback(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0), *port);
    if (fd >= 0) idle.push_back(fd);
  }
  test::pump_for(base, milliseconds(2500));
  const int reader = test::connect_to_loopback(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0), *port);
  ASSERT_GE(reader, 0);
  std::string got;
  bool closed = false;
  for (const auto until = steady_clock::now() + seconds(8); steady_clock::now() < until && !closed;) {
    base.pump(milliseconds(50));
    char buf[4096];
    ssize_t n;
    while ((n = ::recv(reader, buf, sizeof buf, MSG_DONTWAIT)) > 0) got.append(buf, static_cast<std::size_t>(n));
    closed = n == 0;
    if (rtk::Rtcm3Reader().feed(got).size() >= 6) break;
  }
  EXPECT_FALSE(closed) << "the reader was closed\n" << base.stderr_text();
  EXPECT_GE(rtk::Rtcm3Reader().feed(got).size(), 6u) << base.stderr_text();
  ::close(reader);
  for (const int fd : idle) ::close(fd);
  EXPECT_EQ(stop(base), 0) << base.stderr_text();
  const std::string err = base.stderr_text();
  // (How many of the 300 were refused or took an older one's place depends on how fast they were
  // accepted: a loaded machine spreads them over more than 2 s.)
  EXPECT_NE(err.find("closed for a newcomer (most behind)"), std::string::npos) << err;
  EXPECT_EQ(err.find(" 0 closed for a newcomer"), std::string::npos) << err;
  EXPECT_NE(err.find("refused (every slot taken)"), std::string::npos) << err;
}

/// The base at Madison, 10 epochs as fast as they go from a fixed time, to a file.
test::Result run_base_to(const fs::path& file, const std::vector<std::string>& more) {
  std::vector<std::string> argv{GPSEMU_BINARY, "base", "--fast", "--duration", "10", "--start-time", "2024-05-01T12:00:00Z",
                                "--output", "file:" + file.string()};
  argv.insert(argv.end(), more.begin(), more.end());
  return test::run(argv);
}

TEST(BaseStation, RtklibsConvbinDecodesTheObservations) {
  const fs::path dir = test::scratch_dir("base", "convbin");
  const fs::path file = dir / "base.rtcm3", obs = dir / "base.obs";
  const test::Result b = run_base_to(file, {"--msm", "7"});
  ASSERT_EQ(b.status, 0) << b.err;
  const auto r = test::run({"/usr/bin/convbin", "-r", "rtcm3", "-tr", "2024/05/01", "12:00:00", "-o", obs.string(), file.string()});
  ASSERT_EQ(r.status, 0) << "convbin (Debian package rtklib, tools/setup --with-test-deps): " << r.err;
  EXPECT_TRUE(test::contains(r.err, "O=10")) << r.err;  // ten epochs of observations
  EXPECT_FALSE(test::contains(r.err, "E=")) << r.err;   // no message RTKLIB calls an error (a short 1230)
  const std::string rinex = test::read_file(obs);
  for (const char* types : {"G    4 C1C L1C C2L L2L", "R    4 C1C L1C C2C L2C", "E    4 C1C L1C C7Q L7Q"}) {
    EXPECT_TRUE(test::contains(rinex, types)) << types << "\n" << rinex.substr(0, 3000);
  }
  std::istringstream text(rinex.substr(rinex.find("END OF HEADER")));
  std::string line;
  std::getline(text, line);
  int epochs = 0, observations = 0;
  std::set<char> systems;
  for (; std::getline(text, line);) {
    if (line.rfind("> ", 0) == 0) {
      // RINEX in GPS time: UTC + 18 s, one epoch a second.
      EXPECT_EQ(line.substr(2, 19), fmt::format("2024 05 01 12 00 {}", 18 + epochs)) << line;
      ++epochs;
      continue;
    }
    ASSERT_GE(line.size(), 33u) << line;
    systems.insert(line[0]);
    const double pseudorange_m = std::stod(line.substr(3, 14)), phase_cycles = std::stod(line.substr(19, 14));
    EXPECT_GT(pseudorange_m, 1.9e7) << line;  // MEO and IGSO/GEO satellites: 64..140 ms of light
    EXPECT_LT(pseudorange_m, 4.2e7) << line;
    EXPECT_GT(phase_cycles, 9e7) << line;  // the phase range in L1 cycles (GLONASS too: MSM7 has its channel)
    ++observations;
  }
  EXPECT_EQ(epochs, 10);
  EXPECT_GE(observations, 10 * 12);
  for (const char system : {'C', 'E', 'G', 'R'}) EXPECT_TRUE(systems.contains(system)) << system;
  fs::remove_all(dir);
}

TEST(BaseStation, GpsdecodeReadsEveryMessageType) {
  const fs::path dir = test::scratch_dir("base", "gpsdecode");
  const fs::path file = dir / "base.rtcm3";
  const test::Result b = run_base_to(file, {"--station-id", "42", "--antenna-height", "1.25"});
  ASSERT_EQ(b.status, 0) << b.err;
  const auto r = test::run({"/bin/sh", "-c", "gpsdecode -j < '" + file.string() + "'"});
  ASSERT_EQ(r.status, 0) << "gpsdecode (Debian package gpsd-clients): " << r.err;
  std::vector<int> decoded;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    ASSERT_TRUE(test::contains(line, "\"class\":\"RTCM3\"")) << line;
    const auto at = line.find("\"type\":");
    ASSERT_NE(at, std::string::npos) << line;
    decoded.push_back(std::stoi(line.substr(at + 7)));
    if (decoded.back() == 1006 || decoded.back() == 1230) {
      EXPECT_TRUE(test::contains(line, "\"station_id\":42")) << line;
    }
  }
  // Every frame our reader finds, in order (none with a bad CRC or length for gpsd): ten epochs of
  // 1006, the MSM4 of each system in view (GPS and GLONASS always), 1230.
  rtk::Rtcm3Reader reader;
  std::vector<int> written;
  for (const rtk::Rtcm3Frame& f : reader.feed(test::read_file(file))) written.push_back(f.message_type());
  EXPECT_EQ(decoded, written);
  EXPECT_EQ(std::count(decoded.begin(), decoded.end(), 1006), 10);
  EXPECT_EQ(std::count(decoded.begin(), decoded.end(), 1074), 10);
  EXPECT_EQ(std::count(decoded.begin(), decoded.end(), 1084), 10);
  EXPECT_EQ(std::count(decoded.begin(), decoded.end(), 1230), 10);
  ASSERT_FALSE(decoded.empty());
  EXPECT_EQ(decoded.front(), 1006);
  EXPECT_EQ(decoded.back(), 1230);
  fs::remove_all(dir);
}

TEST(BaseStation, WithoutAnOutputItSendsToTheRoversDefaultPort) {
  // Not the emulator's pty:/tmp/gpsemu: the UDP port `gpsemu --rtcm udp:2101` listens on (sending
  // needs no listener, so no port is taken here).
  const test::Result r = test::run({GPSEMU_BINARY, "base", "--fast", "--duration", "2"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(test::contains(r.err, "RTCM3 on udp:127.0.0.1:2101")) << r.err;
  EXPECT_TRUE(test::contains(r.err, "udp:127.0.0.1:2101: 2 epochs written")) << r.err;
}

TEST(BaseStation, BadOptionsExitTwoWithOneLineNamingThem) {
  const struct {
    std::vector<std::string> args;
    const char* named;
  } cases[] = {{{"--msm", "5"}, "--msm"},
               {{"--systems", "GPS,SBAS"}, "'SBAS'"},
               {{"--station-id", "4096"}, "--station-id"},
               {{"--antenna-height", "9"}, "--antenna-height"},
               {{"--rate", "10"}, "--rate does not apply to 'gpsemu base'"},
               {{"--receiver", "ublox-f9p"}, "--receiver does not apply"},
               {{"--clock", "lockstep"}, "lockstep"},
               {{"--output", "udp:nowhere"}, "udp:nowhere"}};
  for (const auto& c : cases) {
    std::vector<std::string> argv{GPSEMU_BINARY, "base", "--duration", "1", "--output", "file:/dev/null"};
    argv.insert(argv.end(), c.args.begin(), c.args.end());
    const test::Result r = test::run(argv);
    EXPECT_EQ(r.status, 2) << c.args[0] << ": " << r.err;
    EXPECT_TRUE(test::contains(r.err, c.named)) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

}  // namespace base_station_test
}  // namespace
}  // namespace gpsemu
