// Reliability: 100,000 malformed datagrams (binary, truncated JSON, wrong types, huge numbers,
// oversize, ...) sent as fast as the sender can, in bursts over about 5 s, to a gpsemu fed by
// valid poses at 50 Hz on the same port. Every epoch from the first fix to the end must arrive on
// the pty exactly once and in order, with a fix and the valid poses' position (--noise none), and
// the end-of-run summary must account for every datagram: poses used + dropped (refused by the
// parser, or dropped by the kernel when the socket buffer was full) = datagrams sent.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/read_deadline.hpp"

namespace gpsemu {
namespace {
namespace pose_udp_flood_test {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr double kLatDeg = 43.0731, kLonDeg = -89.4107, kAltM = 271.5;
constexpr int kMalformed = 100'000;

/// The i-th malformed datagram: every kind of garbage a broken or hostile sender produces, none of
/// which is a valid pose.
std::string malformed(int i, std::mt19937& rng) {
  static const std::vector<std::string> fixed = {
      R"({"lat":"43.07","lon":-89.41})",            // a string as a number
      R"({"lat":true,"lon":-89.41})",               // a bool
      R"({"x":null,"y":1})",                        // null
      R"({"x":[1],"y":2})",                         // an array
      R"({"x":{"v":1},"y":2})",                     // an object
      R"({"lat":1e308,"lon":0})",                   // huge: out of range
      R"({"x":1e400,"y":0})",                       // beyond double range
      R"({"x":123456789012345678901234567890,"y":1})",
      R"({"lat":43.07,"lon":-89.41,"alt":1e12})",
      R"({"x":NaN,"y":1})",
      R"({"lat":91,"lon":0})",
      R"({"x":1})",                                 // half a pair
      R"({"x":1,"y":2,"lat":43,"lon":-89})",        // mixed position forms
      R"({"x":1,"y":2,"speed":3})",                 // unknown key
      R"({"x":1,"y":2,"x":3})",                     // repeated key
      R"([43.07,-89.41])",                          // not an object
      R"("pose")", "42", "{}", "", "\n",
  };
  const std::string valid = R"({"lat":43.0731,"lon":-89.4107,"alt":271.5})";
  switch (i % 5) {
    case 0: {  // binary
      std::string b(1 + rng() % 200, '\0');
      for (auto& c : b) c = static_cast<char>(rng() & 0xff);
      return b;
    }
    case 1: return valid.substr(0, 1 + rng() % (valid.size() - 1));  // truncated JSON
    case 2: return fixed[static_cast<std::size_t>(i / 5) % fixed.size()];
    case 3: return i % 20 == 3 ? std::string(4097 + rng() % 4000, ' ') + valid  // oversize
                               : fixed[static_cast<std::size_t>(i / 5 + 7) % fixed.size()];
    default: return "{\"lat\":" + std::string(3 + rng() % 400, '9') + ",\"lon\":0}";  // 999...: out of range
  }
}

/// One epoch as read from the pty.
struct Epoch {
  std::int64_t time_ms = -1;  ///< RMC time of day
  bool fix = false;           ///< RMC 'A' and GGA quality > 0
  double lat_deg = NAN, lon_deg = NAN, alt_m = NAN;
};

class EpochReader {
 public:
  void feed(std::string_view bytes) {
    for (const auto& s : reader_.feed(bytes)) {
      if (s.type == "RMC") {
        const auto r = nmea::parse_rmc(s);
        if (!r || !r->time_of_day) continue;
        epochs_.push_back({r->time_of_day->count(), r->status_active, NAN, NAN, NAN});
      } else if (s.type == "GGA" && !epochs_.empty()) {
        const auto g = nmea::parse_gga(s);
        if (!g || !g->time_of_day || g->time_of_day->count() != epochs_.back().time_ms) continue;
        auto& e = epochs_.back();
        e.fix = e.fix && g->quality != nmea::FixQuality::none;
        e.lat_deg = g->lat_deg.value_or(NAN);
        e.lon_deg = g->lon_deg.value_or(NAN);
        e.alt_m = g->alt_msl_m.value_or(NAN);
      }
    }
  }
  [[nodiscard]] const std::vector<Epoch>& epochs() const { return epochs_; }
  [[nodiscard]] const nmea::StreamStats& stats() const { return reader_.stats(); }

 private:
  nmea::StreamReader reader_;
  std::vector<Epoch> epochs_;
};

TEST(PoseUdpFloodTest, HundredThousandMalformedDatagramsLeaveEveryEpochWithTheSentPosition) {
  const fs::path dir = test::scratch_root() / ("gpsemu_flood_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path link = dir / "gps";
  test::Process gpsemu({GPSEMU_BINARY, "--source", "udp:127.0.0.1:0", "--rate", "10", "--noise", "none",
                        "--pose-timeout", "5", "--output", "pty:" + link.string(), "--log-level", "info"});
  const auto waiting = gpsemu.wait_for_stderr("waiting for poses on", 20s);
  ASSERT_TRUE(waiting) << gpsemu.stderr_text();
  std::smatch m;
  ASSERT_TRUE(std::regex_search(*waiting, m, std::regex("udp:127\\.0\\.0\\.1:([0-9]+)"))) << *waiting;
  const auto port = static_cast<std::uint16_t>(std::stoi(m[1]));
  ASSERT_TRUE(gpsemu.wait_for_stderr("pty output: /dev/pts", 20s)) << gpsemu.stderr_text();
  const int pty = ::open(link.c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  ASSERT_GE(pty, 0);

  // Valid poses at 50 Hz for the whole run.
  std::atomic<bool> stop_valid{false};
  std::atomic<std::uint64_t> valid_sent{0};
  std::thread valid([&] {
    const int fd = test::udp_to(port);
    const std::string pose = R"({"lat":43.0731,"lon":-89.4107,"alt":271.5})";
    auto next = std::chrono::steady_clock::now();
    while (!stop_valid.load()) {
      if (::send(fd, pose.data(), pose.size(), 0) == static_cast<ssize_t>(pose.size())) ++valid_sent;
      // 20 ms apart even when this thread was held up: never two poses in a burst (gpsemu refuses
      // a pose less than 0.5 ms after the previous one as a flood).
      next = std::max(next + 20ms, std::chrono::steady_clock::now() + 10ms);
      std::this_thread::sleep_until(next);
    }
    ::close(fd);
  });

  EpochReader reader;
  // Reads the pty for `d` or until `done()` holds after a read (or the pty goes away).
  auto read_for = [&](std::chrono::milliseconds d, const std::function<bool()>& done) {
    test::read_with_deadline(pty, {d}, [&](std::string_view chunk) {
      reader.feed(chunk);
      return done();
    });
  };
  auto has_fix = [&] { return !reader.epochs().empty() && reader.epochs().back().fix; };
  read_for(20s, has_fix);
  ASSERT_TRUE(has_fix()) << "no fix from the valid poses\n" << gpsemu.stderr_text();

  // The flood: from another socket, as fast as it can, in bursts of 1000 no closer than 50 ms apart.
  std::atomic<bool> flood_done{false};
  std::uint64_t flood_sent = 0, flood_failed = 0;
  std::thread flood([&] {
    const int fd = test::udp_to(port);
    std::mt19937 rng(12345);
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < kMalformed; ++i) {
      const std::string d = malformed(i, rng);
      if (::send(fd, d.data(), d.size(), 0) == static_cast<ssize_t>(d.size())) ++flood_sent;
      else ++flood_failed;
      if (i % 1000 == 999) std::this_thread::sleep_until(start + (i / 1000 + 1) * 50ms);
    }
    ::close(fd);
    flood_done.store(true);
  });
  const auto flood_start = std::chrono::steady_clock::now();
  // The flood thread ends while epochs keep coming, so a read follows within 100 ms.
  read_for(120s, [&] { return flood_done.load(); });
  flood.join();
  const double flood_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - flood_start).count();
  // Valid poses for 15 epochs more (so the kernel's drop count arrives with a later datagram),
  // then stop them; 3 epochs later gpsemu has waited for an epoch (servicing the socket) since
  // the last pose arrived; stop it while its fix still holds (--pose-timeout 5).
  auto epochs_after = [&](std::size_t n) {
    const std::size_t target = reader.epochs().size() + n;
    return [&reader, target] { return reader.epochs().size() >= target; };
  };
  read_for(30s, epochs_after(15));
  stop_valid.store(true);
  valid.join();
  read_for(30s, epochs_after(3));
  gpsemu.signal(SIGTERM);
  read_for(10s, [] { return false; });
  ::close(pty);
  ASSERT_EQ(gpsemu.wait(20s), 0) << gpsemu.stderr_text();
  fs::remove_all(dir);

  // Every epoch from the first fix on: exactly once, in order, 100 ms apart, with the fix and the
  // position the valid poses carried.
  const auto& epochs = reader.epochs();
  EXPECT_EQ(reader.stats().bad_checksum + reader.stats().malformed, 0u);
  std::size_t first = 0;
  while (first < epochs.size() && !epochs[first].fix) ++first;
  ASSERT_LT(first + 50, epochs.size()) << "too few epochs with a fix";
  std::size_t bad_step = 0, no_fix = 0, off_position = 0;
  for (std::size_t i = first; i < epochs.size(); ++i) {
    const auto& e = epochs[i];
    if (i > first && (e.time_ms - epochs[i - 1].time_ms + 86'400'000) % 86'400'000 != 100) {
      ++bad_step;
      ADD_FAILURE() << "epoch " << e.time_ms << " ms follows " << epochs[i - 1].time_ms << " ms";
    }
    if (!e.fix) ++no_fix;
    if (!(std::abs(e.lat_deg - kLatDeg) < 1e-6 && std::abs(e.lon_deg - kLonDeg) < 1e-6 &&
          std::abs(e.alt_m - kAltM) < 0.05)) {
      ++off_position;
      ADD_FAILURE() << fmt::format("epoch {} ms at {:.7f},{:.7f},{:.2f}", e.time_ms, e.lat_deg, e.lon_deg, e.alt_m);
    }
  }
  EXPECT_EQ(bad_step, 0u);
  EXPECT_EQ(no_fix, 0u);
  EXPECT_EQ(off_position, 0u);

  // The summary accounts for every datagram.
  EXPECT_EQ(flood_sent, static_cast<std::uint64_t>(kMalformed)) << flood_failed << " sends failed";
  const std::string err = gpsemu.stderr_text();
  std::smatch s;
  ASSERT_TRUE(std::regex_search(err, s, std::regex("pose input udp:[^ ]+: ([0-9]+) poses used, ([0-9]+) dropped"
                                                   "(?: by reason: ([^;]*))?;")))
      << err;
  const std::uint64_t used = std::stoull(s[1]), dropped = std::stoull(s[2]);
  std::map<std::string, std::uint64_t> reasons;
  const std::string reason_text = s[3];
  const std::regex reason_count("([a-z_]+) ([0-9]+)");
  for (auto it = std::sregex_iterator(reason_text.begin(), reason_text.end(), reason_count);
       it != std::sregex_iterator(); ++it) {
    reasons[(*it)[1]] = std::stoull((*it)[2]);
  }
  const std::uint64_t kernel = reasons["kernel_overflow"];
  std::uint64_t by_reason = 0;
  for (const auto& [name, n] : reasons) by_reason += n;
  EXPECT_EQ(by_reason, dropped) << reason_text;
  EXPECT_EQ(used + dropped, valid_sent.load() + flood_sent) << err;
  const std::uint64_t refused = dropped - kernel;  // read and refused by gpsemu itself
  EXPECT_GT(refused, 0u);
  EXPECT_LE(refused, static_cast<std::uint64_t>(kMalformed));
  for (const char* never : {"other_sender", "flood", "out_of_order", "too_many_clients"}) {
    EXPECT_EQ(reasons.count(never), 0u) << never << " in " << reason_text;
  }
  EXPECT_GT(used, 0u);
  EXPECT_LE(used, valid_sent.load());
  std::printf("flood: %llu malformed datagrams in %.1f s beside %llu valid poses; gpsemu refused %llu, the kernel "
              "dropped %llu (of either kind), %llu poses used; %zu epochs with a fix, all in order (by reason: %s)\n",
              static_cast<unsigned long long>(flood_sent), flood_s, static_cast<unsigned long long>(valid_sent.load()),
              static_cast<unsigned long long>(refused), static_cast<unsigned long long>(kernel),
              static_cast<unsigned long long>(used), epochs.size() - first, reason_text.c_str());
}

}  // namespace pose_udp_flood_test
}  // namespace
}  // namespace gpsemu
