// End to end through a real pseudo-terminal: the gpsemu binary streams, a client reads with
// poll() and a timeout, as gpsd would.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <cmath>

#include <fmt/format.h>

#include "nmea/sentences.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace pty_loopback_test {

namespace fs = std::filesystem;
using namespace std::chrono;

fs::path temp_dir(const std::string& name) { return test::scratch_dir("it", name); }

int open_client(const fs::path& link) {
  const int fd = ::open(link.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd >= 0) {
    termios t{};
    tcgetattr(fd, &t);
    cfmakeraw(&t);
    tcsetattr(fd, TCSANOW, &t);
  }
  return fd;
}

/// Reads whatever arrives for `how_long` or until the writer goes away, each read with its
/// CLOCK_REALTIME time.
std::vector<test::Chunk> read_for(int fd, milliseconds how_long) {
  std::vector<test::Chunk> out;
  test::read_with_deadline(fd, {how_long}, [&](std::string_view bytes) {
    out.push_back({test::realtime_now_s(), std::string(bytes)});
    return false;
  });
  return out;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0, nl;
  while ((nl = text.find("\r\n", start)) != std::string::npos) {
    lines.push_back(text.substr(start, nl - start));
    start = nl + 2;
  }
  return lines;
}

bool checksum_ok(const std::string& line) {
  const auto star = line.rfind('*');
  if (line.empty() || line[0] != '$' || star == std::string::npos || star + 3 != line.size()) return false;
  return fmt::format("{:02X}", nmea::checksum(std::string_view(line).substr(1, star - 1))) == line.substr(star + 1);
}

std::string field(const std::string& line, int index) {
  std::size_t start = 0;
  for (int i = 0; i < index; ++i) start = line.find(',', start) + 1;
  return line.substr(start, line.find_first_of(",*", start) - start);
}

/// hhmmss.ss -> seconds of the day
double time_of_day_s(const std::string& t) {
  return std::stoi(t.substr(0, 2)) * 3600.0 + std::stoi(t.substr(2, 2)) * 60.0 + std::stod(t.substr(4));
}

TEST(PtyLoopback, TenHertzDeliversEveryEpochOnTimeWithValidChecksums) {
  const auto dir = temp_dir("10hz");
  const auto link = dir / "gps";
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--duration", "4", "--latency", "0.05",
                        "--output", "pty:" + link.string(), "--seed", "3", "--sentences", "GGA,RMC"});
  ASSERT_TRUE(gpsemu.wait_for_stderr("NMEA on", seconds(10))) << gpsemu.stderr_text();
  const int fd = open_client(link);
  ASSERT_GE(fd, 0) << "cannot open " << link;
  const auto arrivals = read_for(fd, milliseconds(4500));
  ::close(fd);
  ASSERT_EQ(gpsemu.wait(seconds(10)), 0) << gpsemu.stderr_text();

  // Group lines by epoch, remembering when each epoch's first bytes arrived.
  std::string all;
  std::vector<std::pair<std::size_t, double>> chunk_starts;
  for (const auto& a : arrivals) {
    chunk_starts.emplace_back(all.size(), a.read_s);
    all += a.bytes;
  }
  const auto lines = lines_of(all);
  ASSERT_GE(lines.size(), 70u) << all;  // 40 epochs x 2 sentences, a few may precede the client
  std::vector<double> gga_times;
  std::map<std::string, int> per_time;
  for (const auto& l : lines) {
    EXPECT_TRUE(checksum_ok(l)) << l;
    EXPECT_LE(l.size() + 2, 82u) << l;
    const std::string type = l.substr(3, 3);
    ASSERT_TRUE(type == "GGA" || type == "RMC") << l;
    ++per_time[field(l, 1)];
    if (type == "GGA") gga_times.push_back(time_of_day_s(field(l, 1)));
  }
  for (const auto& [t, n] : per_time) EXPECT_EQ(n, 2) << "epoch " << t << " has " << n << " sentences";
  for (std::size_t i = 1; i < gga_times.size(); ++i) {
    EXPECT_NEAR(gga_times[i] - gga_times[i - 1], 0.1, 1e-6) << "between epochs " << i - 1 << " and " << i;
  }
  // Bytes of epoch t never leave before t + latency (checked on each read that starts an epoch).
  double worst_early_s = 0.0, sum_offset = 0.0;
  int measured = 0;
  for (const auto& [offset, wall] : chunk_starts) {
    if (all.compare(offset, 6, "$GNRMC") != 0) continue;  // an epoch starts with RMC (u-blox order)
    const std::string line = all.substr(offset, all.find("\r\n", offset) - offset);
    const double day_s = std::fmod(wall, 86400.0);
    const double delta = day_s - time_of_day_s(field(line, 1));
    worst_early_s = std::min(worst_early_s, delta - 0.05);
    sum_offset += delta;
    ++measured;
  }
  ASSERT_GT(measured, 30);
  EXPECT_GT(worst_early_s, -0.001) << "an epoch arrived before epoch time + latency";
  RecordProperty("mean_arrival_offset_ms", std::to_string(1000.0 * sum_offset / measured));
  EXPECT_FALSE(fs::exists(link)) << "the symlink outlives the emulator";
}

TEST(PtyLoopback, ClientWritingGarbageAndReopeningKeepsReceiving) {
  const auto dir = temp_dir("reopen");
  const auto link = dir / "gps";
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--output", "pty:" + link.string()});
  ASSERT_TRUE(gpsemu.wait_for_stderr("NMEA on", seconds(10))) << gpsemu.stderr_text();
  for (int round = 0; round < 5; ++round) {
    const int fd = open_client(link);
    ASSERT_GE(fd, 0);
    const std::string probe(8192, '\x55');  // gpsd-style probing: kilobytes of bytes the receiver ignores
    ASSERT_EQ(::write(fd, probe.data(), probe.size()), static_cast<ssize_t>(probe.size()));
    std::string got;
    for (const auto& a : read_for(fd, milliseconds(400))) got += a.bytes;
    ::close(fd);
    EXPECT_NE(got.find("GGA"), std::string::npos) << "round " << round;
  }
  gpsemu.signal(SIGTERM);
  EXPECT_EQ(gpsemu.wait(seconds(10)), 0) << gpsemu.stderr_text();
  EXPECT_FALSE(fs::exists(link));
}

std::string fast_run(const std::string& seed, const std::string& source = "sim:circle") {
  const auto r = test::run({GPSEMU_BINARY, "--fast", "--duration", "300", "--rate", "10", "--seed", seed,
                            "--source", source, "--start-time", "2024-02-28T23:59:00Z", "--output", "stdout",
                            "--log-level", "warn"});
  EXPECT_EQ(r.status, 0) << r.err;
  return r.out;
}

TEST(FastMode, SameSeedAndStartTimeAreByteIdenticalAndAnotherSeedDiffers) {
  const std::string a = fast_run("42"), b = fast_run("42"), c = fast_run("43");
  const auto lines = lines_of(a);  // the default set: RMC first in every epoch
  EXPECT_EQ(std::count_if(lines.begin(), lines.end(), [](const std::string& l) { return l.compare(3, 3, "RMC") == 0; }),
            3000);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(FastMode, ReportsMissingOutputDirectoryAtStartUpWithStatus2) {
  const auto r = test::run({GPSEMU_BINARY, "--fast", "--duration", "1", "--output", "file:/nonexistent/dir/x.nmea"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("/nonexistent/dir/x.nmea"), std::string::npos) << r.err;
}

}  // namespace pty_loopback_test
}  // namespace
}  // namespace gpsemu
