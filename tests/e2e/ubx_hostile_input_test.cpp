// What held up against a hostile u-blox client in issue 22 and must keep holding, end to end on
// the gpsemu binary and a real pty, each a few seconds:
// - random bytes written as fast as the pty takes them: the memory stays flat and every epoch
//   leaves on time (each NAV-PVT read within a fraction of a second of its own time);
// - a storm of mixed polls (MON-VER, CFG-RATE, CFG-PRT, CFG-MSG, NAV-PVT) at about 10 000 a second
//   from a client that reads as it writes: every MON-VER answered, every frame counted read;
// - SIGTERM and SIGINT at any moment of start-up: the process ends at once, and leaves no link.
// (The sweep of every class and id, 0xFFFF lengths and truncation, and the CFG edge matrix are
// in-process: tests/unit/ubx/hostile_input_test.cpp; duplicate instances:
// tests/e2e/duplicate_outputs_test.cpp.)
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/socat_pair.hpp"

namespace gpsemu {
namespace {
namespace ubx_hostile_input_test {

namespace fs = std::filesystem;
using namespace std::chrono;
using Clock = steady_clock;

std::uint64_t rss_kb(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stoull(line.substr(6));
  }
  return 0;
}

double wall_s() { return duration<double>(system_clock::now().time_since_epoch()).count(); }

/// A u-blox F9P at 10 Hz on a pty (UBX: NAV-PVT each epoch), a raw client descriptor on it.
struct Receiver {
  fs::path dir;
  fs::path link;
  std::unique_ptr<test::Process> gpsemu;
  int fd = -1;

  explicit Receiver(const std::string& name) {
    dir = test::scratch_dir("ubx_hostile", name);
    link = dir / "gps";
    gpsemu = std::make_unique<test::Process>(std::vector<std::string>{
        GPSEMU_BINARY, "--protocol", "ubx", "--receiver", "ublox-f9p", "--rate", "10", "--noise", "none", "--output",
        "pty:" + link.string(), "--log-level", "info"});
    if (!gpsemu->wait_for_stderr("UBX on", seconds(20))) throw std::runtime_error(gpsemu->stderr_text());
    fd = test::open_raw(link);
  }
  ~Receiver() {
    if (fd >= 0) ::close(fd);
    fs::remove_all(dir);
  }
  /// Closes the client and stops gpsemu: its standard error.
  std::string stop() {
    ::close(fd);
    fd = -1;
    gpsemu->signal(SIGTERM);
    EXPECT_EQ(gpsemu->wait(seconds(10)), 0) << gpsemu->stderr_text();
    return gpsemu->stderr_text();
  }
};

/// Everything the client read: UBX frames, NMEA sentences (with when they were read).
struct Heard {
  ubx::FrameReader reader;
  std::vector<ubx::Frame> frames;
  std::vector<std::pair<double, double>> pvts;  ///< each NAV-PVT: read time, its own UTC time of day (s)
  void feed(std::string_view bytes) {
    const double now = wall_s();
    for (auto& m : reader.feed(bytes)) {
      auto* f = std::get_if<ubx::Frame>(&m);
      if (f == nullptr) continue;
      if (f->id == ubx::msg::nav_pvt && f->payload.size() >= 20) {
        const auto u1 = [&](std::size_t at) { return static_cast<std::uint8_t>(f->payload[at]); };
        const auto nano = static_cast<std::int32_t>(static_cast<std::uint32_t>(u1(16)) | u1(17) << 8 | u1(18) << 16 |
                                                    static_cast<std::uint32_t>(u1(19)) << 24);
        pvts.emplace_back(now, u1(8) * 3600.0 + u1(9) * 60.0 + u1(10) + nano * 1e-9);
      }
      frames.push_back(std::move(*f));
    }
  }
  [[nodiscard]] std::size_t count(ubx::MessageId id) const {
    std::size_t n = 0;
    for (const auto& f : frames) n += f.id == id ? 1 : 0;
    return n;
  }
};

/// For `how_long`: writes what `next` gives (as fast as the pty takes it, or `pace` per write)
/// while reading everything that comes back into `heard`. Bytes written.
template <class Next>
std::uint64_t talk(int fd, Heard& heard, milliseconds how_long, milliseconds pace, Next next) {
  const auto end = Clock::now() + how_long;
  auto next_write = Clock::now();
  std::uint64_t written = 0;
  std::string pending;
  std::vector<char> buf(65536);
  while (Clock::now() < end) {
    if (pending.empty() && Clock::now() >= next_write) {
      pending = next();
      next_write += pace;
    }
    pollfd p{fd, static_cast<short>(POLLIN | (pending.empty() ? 0 : POLLOUT)), 0};
    if (::poll(&p, 1, 5) <= 0) continue;
    if ((p.revents & POLLOUT) && !pending.empty()) {
      const ssize_t n = ::write(fd, pending.data(), pending.size());
      if (n > 0) {
        written += static_cast<std::uint64_t>(n);
        pending.erase(0, static_cast<std::size_t>(n));
      }
    }
    if (p.revents & POLLIN) {
      const ssize_t n = ::read(fd, buf.data(), buf.size());
      if (n > 0) heard.feed({buf.data(), static_cast<std::size_t>(n)});
    }
  }
  return written;
}

std::uint64_t number_in(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) return 0;
  return std::stoull(m[1]);
}

TEST(UbxHostileInput, RandomBytesAtTheHighestRateKeepTheMemoryFlatAndTheEpochsOnTime) {
  Receiver r("random");
  std::mt19937_64 random(22);
  std::string noise(64 * 1024, '\0');
  Heard heard;
  // A first second to settle, then the RSS to compare with; then 4 s more.
  (void)talk(r.fd, heard, milliseconds(1000), milliseconds(0), [&] {
    for (auto& c : noise) c = static_cast<char>(random());
    return noise;
  });
  const std::uint64_t rss_before_kb = rss_kb(r.gpsemu->pid());
  const auto begin = Clock::now();
  const std::uint64_t written = talk(r.fd, heard, milliseconds(4000), milliseconds(0), [&] {
    for (std::size_t k = 0; k < noise.size(); k += 8) {
      const std::uint64_t v = random();
      for (int b = 0; b < 8; ++b) noise[k + b] = static_cast<char>(v >> (8 * b));
    }
    return noise;
  });
  const double seconds_taken = duration<double>(Clock::now() - begin).count();
  const std::uint64_t rss_after_kb = rss_kb(r.gpsemu->pid());
  const std::string err = r.stop();

  // Every epoch on time: each NAV-PVT read within half a second of its own time, 10 a second.
  double worst_age_s = 0.0;
  for (const auto& [read_s, own_s] : heard.pvts) {
    const double age_s = std::fmod(read_s - own_s + 86400.0 + 43200.0, 86400.0) - 43200.0;
    worst_age_s = std::max(worst_age_s, age_s);
  }
  EXPECT_GE(heard.pvts.size(), 45u) << "5 s at 10 Hz\n" << err;
  EXPECT_LT(worst_age_s, 0.5) << err;
  EXPECT_LT(rss_after_kb, rss_before_kb + 2048) << "RSS " << rss_before_kb << " -> " << rss_after_kb << " kB";
  EXPECT_GE(number_in(err, "([0-9]+) garbage bytes"), written / 4) << "the bytes read are counted\n" << err;
  std::printf("figure: random bytes at %.1f MB/s for %.1f s: RSS %llu -> %llu kB, %zu NAV-PVT, worst age %.3f s\n",
              static_cast<double>(written) / seconds_taken / 1e6, seconds_taken,
              static_cast<unsigned long long>(rss_before_kb), static_cast<unsigned long long>(rss_after_kb),
              heard.pvts.size(), worst_age_s);
}

TEST(UbxHostileInput, AStormOfMixedPollsHasEveryMonVerAnswered) {
  Receiver r("storm");
  // 100 polls each 10 ms (10 000 a second): MON-VER, CFG-RATE, CFG-PRT (UART1), CFG-MSG NAV-PVT,
  // NAV-PVT (answered with the next solution, once a kind).
  const std::string mon_ver = ubx::frame_bytes(ubx::msg::mon_ver, "");
  std::string batch;
  for (int k = 0; k < 20; ++k) {
    batch += mon_ver;
    batch += ubx::frame_bytes(ubx::msg::cfg_rate, "");
    batch += ubx::frame_bytes(ubx::msg::cfg_prt, std::string(1, '\x01'));
    batch += ubx::frame_bytes(ubx::msg::cfg_msg, std::string{'\x01', '\x07'});
    batch += ubx::frame_bytes(ubx::msg::nav_pvt, "");
  }
  std::uint64_t batches = 0;
  Heard heard;
  (void)talk(r.fd, heard, milliseconds(4000), milliseconds(10), [&] {
    ++batches;
    return batch;
  });
  // The answers to the last batch.
  (void)talk(r.fd, heard, milliseconds(500), milliseconds(100000), [] { return std::string(); });
  const std::string err = r.stop();
  const std::uint64_t sent_mon_ver = 20 * batches;
  EXPECT_GE(batches, 200u) << "4 s of 10 ms batches on a loaded machine";
  EXPECT_EQ(number_in(err, "u-blox client input: ([0-9]+) UBX frames"), 100 * batches) << err;
  EXPECT_EQ(heard.count(ubx::msg::mon_ver), sent_mon_ver) << "every MON-VER answered\n" << err;
  EXPECT_EQ(err.find("dropped whole"), std::string::npos) << "a client reading as it writes loses no answer\n" << err;
  EXPECT_EQ(heard.reader.stats().bad_checksum, 0u);
  EXPECT_GE(heard.count(ubx::msg::nav_pvt), 30u) << "solutions go on during the storm";
  std::printf("figure: mixed poll storm: %llu polls in 4 s, %zu of %llu MON-VER answered, %zu NAV-PVT\n",
              static_cast<unsigned long long>(100 * batches), heard.count(ubx::msg::mon_ver),
              static_cast<unsigned long long>(sent_mon_ver), heard.count(ubx::msg::nav_pvt));
}

TEST(UbxHostileInput, ASignalAtAnyMomentOfStartUpEndsTheRunAtOnceAndLeavesNoLink) {
  const fs::path dir = test::scratch_dir("ubx_hostile", "startup");
  std::size_t clean = 0;
  for (const int sig : {SIGTERM, SIGINT}) {
    for (const int after_ms : {0, 2, 5, 10, 20, 40, 80, 160}) {
      const fs::path link = dir / ("gps" + std::to_string(sig) + "_" + std::to_string(after_ms));
      test::Process gpsemu({GPSEMU_BINARY, "--protocol", "ubx", "--receiver", "ublox-m8n", "--rate", "10", "--output",
                            "pty:" + link.string(), "--log-level", "info"});
      std::this_thread::sleep_for(milliseconds(after_ms));
      gpsemu.signal(sig);
      const int status = gpsemu.wait(seconds(10));
      // Before its handlers are installed the default action kills it (128 + signal); after,
      // it stops cleanly with 0.
      EXPECT_TRUE(status == 0 || status == 128 + sig)
          << "signal " << sig << " after " << after_ms << " ms: status " << status << "\n" << gpsemu.stderr_text();
      clean += status == 0 ? 1 : 0;
      EXPECT_FALSE(fs::exists(fs::symlink_status(link)))
          << "signal " << sig << " after " << after_ms << " ms left the link\n" << gpsemu.stderr_text();
    }
  }
  std::printf("figure: 16 signals during start-up: %zu clean exits, the others before the handlers\n", clean);
  fs::remove_all(dir);
}

}  // namespace ubx_hostile_input_test
}  // namespace
}  // namespace gpsemu
