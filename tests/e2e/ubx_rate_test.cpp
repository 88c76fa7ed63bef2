// A u-blox client changes the receiver's epoch rate and its line's speed, end to end on the gpsemu
// binary: on a real pty at --rate 1, CFG-RATE 200 ms then 100 ms is acknowledged and NAV-PVT
// follows (iTOW on the new grid, the count per second too), 50 ms on an M8N gives its fastest
// 10 Hz, 1000 ms brings 1 Hz back; on a serial line (socat pty pair) switched to 9600 baud at
// 10 Hz, the TX buffer drops whole messages only and the summary counts them. The start-up lines
// say what a u-blox receiver writes and its widest epoch with the UBX bytes. In a fleet (a config
// file's [[receiver]] tables), CFG-RATE 200 ms speeds up the u-blox on its pty alone: its NAV-PVT
// come 5 a second while the NMEA receiver beside it keeps one GGA each whole second, and the
// summary's per-receiver lines count what each wrote.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/nmea_check.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/socat_pair.hpp"

namespace gpsemu {
namespace {
namespace ubx_rate_test {

using namespace std::chrono;

std::string cfg_rate(std::uint16_t meas_ms) {
  std::string p;
  ubx::put_u2(p, meas_ms);
  ubx::put_u2(p, 1);  // navRate
  ubx::put_u2(p, 1);  // GPS time
  return ubx::frame_bytes(ubx::msg::cfg_rate, p);
}

std::string cfg_prt_uart1(std::uint32_t baud) {
  std::string p;
  ubx::put_u1(p, 1);  // UART1
  ubx::put_u1(p, 0);
  ubx::put_u2(p, 0);
  ubx::put_u4(p, 0x08D0);  // 8N1
  ubx::put_u4(p, baud);
  ubx::put_u2(p, 0x0007);  // in: UBX, NMEA, RTCM3
  ubx::put_u2(p, 0x0003);  // out: UBX, NMEA
  ubx::put_u2(p, 0);
  ubx::put_u2(p, 0);
  return ubx::frame_bytes(ubx::msg::cfg_prt, p);
}

/// What the client read: the frames and sentences in order (FrameReader checks every checksum).
struct Heard {
  ubx::FrameReader reader;
  std::vector<ubx::Frame> frames;
  std::uint64_t sentences = 0;

  void feed(std::string_view bytes) {
    for (auto& m : reader.feed(bytes)) {
      if (auto* f = std::get_if<ubx::Frame>(&m)) {
        frames.push_back(std::move(*f));
      } else {
        ++sentences;
      }
    }
  }
  void read(int fd, milliseconds how_long) {
    (void)test::read_with_deadline(fd, {how_long}, [&](std::string_view bytes) {
      feed(bytes);
      return false;
    });
  }
  /// iTOW of each NAV-PVT from frame `from` on, counted on from the week of `week_of` (an iTOW
  /// heard in this run; by default the first NAV-PVT of these frames): a run crossing the GPS week's
  /// end (Saturday 23:59:42 UTC) goes on past 604 800 000 ms instead of back to 0, so its spacing
  /// and span stay what they are (a run at that minute once failed on the wrap).
  [[nodiscard]] std::vector<std::uint32_t> pvt_itow(std::size_t from = 0,
                                                    std::optional<std::uint32_t> week_of = {}) const {
    constexpr auto kWeekMs = static_cast<std::uint32_t>(std::chrono::milliseconds(std::chrono::weeks{1}).count());
    std::vector<std::uint32_t> out;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      if (frames[k].id != ubx::msg::nav_pvt) continue;
      std::uint32_t itow = ubx::get_u4(frames[k].payload, 0);
      if (!week_of) week_of = itow;
      if (itow + kWeekMs / 2 < *week_of) itow += kWeekMs;  // the next week's
      if (k >= from) out.push_back(itow);
    }
    return out;
  }
  /// Index just past the ACK-ACK of `id`, or nothing.
  [[nodiscard]] std::optional<std::size_t> after_ack(ubx::MessageId id, std::size_t from) const {
    for (std::size_t k = from; k < frames.size(); ++k) {
      if (frames[k].id == ubx::msg::ack_ack && frames[k].payload.size() == 2 &&
          static_cast<std::uint8_t>(frames[k].payload[0]) == id.msg_class &&
          static_cast<std::uint8_t>(frames[k].payload[1]) == id.msg_id) {
        return k + 1;
      }
    }
    return std::nullopt;
  }
};

void write_all(int fd, const std::string& bytes) {
  ASSERT_EQ(::write(fd, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
}

/// Asks for `meas_ms`, reads for `how_long`, and checks that the last `tail` NAV-PVT are
/// `spacing_ms` apart on that grid.
void expect_rate(int fd, Heard& heard, std::uint16_t meas_ms, std::uint32_t spacing_ms, milliseconds how_long,
                 std::size_t tail) {
  const std::size_t from = heard.frames.size();
  write_all(fd, cfg_rate(meas_ms));
  heard.read(fd, how_long);
  const auto acked = heard.after_ack(ubx::msg::cfg_rate, from);
  ASSERT_TRUE(acked) << "no ACK-ACK for CFG-RATE " << meas_ms << " ms";
  const std::vector<std::uint32_t> itow = heard.pvt_itow(*acked);
  ASSERT_GE(itow.size(), tail + 1) << "CFG-RATE " << meas_ms << " ms";
  for (std::size_t k = itow.size() - tail; k < itow.size(); ++k) {
    EXPECT_EQ(itow[k] - itow[k - 1], spacing_ms) << "CFG-RATE " << meas_ms << " ms, solution " << k;
    EXPECT_EQ(itow[k] % spacing_ms, 0u) << "on the grid of the week";
  }
  // The count per second follows: the last whole second holds 1000 / spacing solutions.
  const std::uint32_t last_second = itow.back() / 1000 * 1000 - 1000;
  std::size_t in_second = 0;
  for (const std::uint32_t t : itow) in_second += t >= last_second && t < last_second + 1000 ? 1 : 0;
  EXPECT_EQ(in_second, 1000 / spacing_ms) << "CFG-RATE " << meas_ms << " ms";
}

TEST(UbxRate, CfgRateChangesTheEpochRateOnAPtyAndTheStartUpLineSaysUbx) {
  const auto dir = test::scratch_dir("ubx_rate", "pty");
  const auto link = dir / "gps";
  test::Process gpsemu({GPSEMU_BINARY, "--protocol", "ubx", "--receiver", "ublox-m8n", "--rate", "1", "--noise",
                        "none", "--output", "pty:" + link.string(), "--duration", "20", "--log-level", "info"});
  const auto opened = gpsemu.wait_for_stderr("UBX on", seconds(20));
  ASSERT_TRUE(opened) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find("receiver: u-blox ublox-m8n"), std::string::npos) << gpsemu.stderr_text();
  // NAV-PVT alone: 92 + 8 bytes.
  EXPECT_NE(gpsemu.stderr_text().find("100 bytes an epoch at most (UBX)"), std::string::npos) << gpsemu.stderr_text();
  const int fd = test::open_raw(link);

  Heard heard;
  heard.read(fd, milliseconds(2300));
  const std::vector<std::uint32_t> start = heard.pvt_itow();
  ASSERT_GE(start.size(), 2u);
  EXPECT_EQ(start.back() - start[start.size() - 2], 1000u) << "--rate 1";

  expect_rate(fd, heard, 200, 200, milliseconds(2600), 6);
  expect_rate(fd, heard, 100, 100, milliseconds(2600), 12);
  expect_rate(fd, heard, 50, 100, milliseconds(2600), 12);  // an M8N navigates at 10 Hz at most
  expect_rate(fd, heard, 1000, 1000, milliseconds(3300), 1);
  ::close(fd);
  gpsemu.signal(SIGINT);
  EXPECT_EQ(gpsemu.wait(seconds(10)), 0);
  const std::string log = gpsemu.stderr_text();
  // The wait for the old grid's next epoch was given up, not taken for a wall clock that went back.
  EXPECT_EQ(log.find("wall clock went back"), std::string::npos) << log;
  EXPECT_NE(log.find("u-blox CFG-RATE: a solution every 200 ms"), std::string::npos) << log;
  EXPECT_NE(log.find("navigates at most every 100 ms"), std::string::npos) << log;
}

TEST(UbxRate, ABaudTooSlowForTheEpochDropsWholeMessagesAndTheSummaryCountsThem) {
  const auto dir = test::scratch_dir("ubx_rate", "baud");
  test::SocatPair pair(dir / "A", dir / "B");
  const int fd = test::open_raw(pair.b());
  test::Process gpsemu({GPSEMU_BINARY, "--protocol", "nmea+ubx", "--receiver", "ublox-m8n", "--rate", "10",
                        "--output", "serial:" + pair.a().string() + "@230400", "--duration", "5", "--log-level",
                        "info"});
  ASSERT_TRUE(gpsemu.wait_for_stderr("NMEA+UBX on", seconds(20))) << gpsemu.stderr_text();
  const std::string banner = gpsemu.stderr_text();
  std::smatch widest;
  std::regex_search(banner, widest, std::regex(R"((\d+) bytes an epoch at most \(NMEA\+UBX\))"));
  ASSERT_FALSE(widest.empty()) << gpsemu.stderr_text();
  EXPECT_GT(std::stoul(widest[1]), 100u) << "the NMEA sentences and NAV-PVT";

  Heard heard;
  heard.read(fd, milliseconds(800));
  const std::uint64_t sentences_before = heard.sentences;
  ASSERT_GT(sentences_before, 0u);
  write_all(fd, cfg_prt_uart1(9600));
  heard.read(fd, seconds(8));  // until the run ends
  EXPECT_TRUE(heard.after_ack(ubx::msg::cfg_prt, 0)) << "CFG-PRT acknowledged";
  // Whole sentences and frames only: every checksum checks, nothing but CR LF between them.
  const ubx::FrameStats& s = heard.reader.stats();
  EXPECT_EQ(s.bad_checksum, 0u);
  EXPECT_EQ(s.bad_sentences, 0u);
  EXPECT_LE(s.garbage_bytes, 2 * s.sentences_ok);
  EXPECT_GT(heard.sentences, sentences_before) << "what fits still goes out";

  EXPECT_EQ(gpsemu.wait(seconds(10)), 0);
  const std::string log = gpsemu.stderr_text();
  EXPECT_NE(log.find("does not fit the line: 9600 baud carries 96 bytes a 100 ms epoch"), std::string::npos) << log;
  std::smatch dropped;
  ASSERT_TRUE(std::regex_search(log, dropped, std::regex(R"(u-blox TX buffer: (\d+) messages \((\d+) bytes\) dropped)")))
      << log;
  EXPECT_GT(std::stoul(dropped[1]), 20u) << "NAV-PVT (100 bytes) never fits 96 bytes: dropped every epoch";
  ::close(fd);
}

/// The first number `pattern` captures in `log`, or nothing.
std::optional<std::uint64_t> number_in(const std::string& log, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(log, m, std::regex(pattern))) return std::nullopt;
  return std::stoull(m[1]);
}

/// Milliseconds of the day of an NMEA time field "hhmmss.ss".
std::int64_t nmea_ms_of_day(const std::string& t) {
  return (std::stoll(t.substr(0, 2)) * 3600 + std::stoll(t.substr(2, 2)) * 60) * 1000 +
         std::llround(std::stod(t.substr(4)) * 1000);
}

TEST(UbxRate, InAFleetCfgRateSpeedsUpTheUbloxAloneAndTheSummaryCountsEachReceiver) {
  const auto dir = test::scratch_dir("ubx_rate", "fleet");
  const auto link = dir / "gps0", ubx_copy = dir / "gps0.ubx", nmea = dir / "gps1.nmea";
  constexpr int duration_s = 8;
  // Receiver 0 a u-blox M8N on a pty (and a file copy of what it writes), receiver 1 NMEA at 1 Hz.
  const auto config = test::write_file(dir / "fleet.toml", fmt::format(R"(rate = 1
duration = {}
noise = "none"
log-level = "info"
[[receiver]]
protocol = "ubx"
receiver = "ublox-m8n"
output = ["pty:{}", "file:{}"]
[[receiver]]
output = "file:{}"
)",
                                                                          duration_s, link.string(), ubx_copy.string(),
                                                                          nmea.string()));
  test::Process gpsemu({GPSEMU_BINARY, "--config", config.string()});
  ASSERT_TRUE(gpsemu.wait_for_stderr("receiver 1: NMEA on", seconds(20))) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find("receiver 0: UBX on"), std::string::npos) << gpsemu.stderr_text();
  const int fd = test::open_raw(link);
  Heard heard;
  heard.read(fd, milliseconds(2300));
  ASSERT_GE(heard.pvt_itow().size(), 2u) << "1 Hz before the change";
  expect_rate(fd, heard, 200, 200, milliseconds(3600), 6);  // ACK-ACK, 200 ms apart, on the grid, 5 a second
  ::close(fd);
  ASSERT_EQ(gpsemu.wait(seconds(10)), 0);
  const std::string log = gpsemu.stderr_text();
  // The wait for the old grid's next epoch was given up, not taken for a wall clock that went back.
  EXPECT_EQ(log.find("wall clock went back"), std::string::npos) << log;

  // Receiver 0: every NAV-PVT it wrote is in the file copy; the summary counts them, byte for byte.
  const std::string ubx_bytes = test::read_file(ubx_copy);
  Heard copy;
  copy.feed(ubx_bytes);
  const std::vector<std::uint32_t> itow = copy.pvt_itow();
  ASSERT_GE(itow.size(), 2u);
  // 1 Hz until the change, then at once on the 200 ms grid (the first step a multiple of 200 ms
  // under a second), 200 ms apart to the end of the run (the last second of --duration).
  std::size_t fast = 0;
  for (std::size_t k = 1; k < itow.size(); ++k) {
    const std::uint32_t step = itow[k] - itow[k - 1];
    if (fast == 0 && step == 1000u) continue;
    if (fast == 0) {
      EXPECT_EQ(step % 200u, 0u) << "solution " << k << ": the first of the new grid";
      EXPECT_LT(step, 1000u) << "solution " << k << ": the new rate at once, not at the next 1 Hz epoch";
    } else {
      EXPECT_EQ(step, 200u) << "solution " << k;
    }
    ++fast;
  }
  EXPECT_GE(fast, 5u * (duration_s - 4)) << "5 a second from the change to the end";
  EXPECT_EQ(itow.back() - itow.front(), duration_s * 1000u - 200u) << "the u-blox runs as long as the fleet";
  const std::vector<std::uint32_t> on_pty = heard.pvt_itow(*heard.after_ack(ubx::msg::cfg_rate, 0), itow.front());
  for (const std::uint32_t t : on_pty) EXPECT_TRUE(std::binary_search(itow.begin(), itow.end(), t)) << t;
  EXPECT_EQ(number_in(log, R"(receiver 0: (\d+) epochs \(0 without fix\))"), itow.size()) << log;
  EXPECT_EQ(number_in(log, "receiver 0: file " + ubx_copy.string() + R"(: (\d+) epochs written)"), itow.size()) << log;
  EXPECT_EQ(number_in(log, "receiver 0: file " + ubx_copy.string() + R"(: \d+ epochs written \((\d+) bytes\))"),
            ubx_bytes.size())
      << log;
  // The pty got the same epochs; the ACK-ACK's 10 bytes are counted apart, as a reply.
  EXPECT_EQ(number_in(log, R"(receiver 0: /dev/pts/\d+ \(link [^)]*\): (\d+) epochs written)"), itow.size()) << log;
  EXPECT_EQ(number_in(log, R"(receiver 0: /dev/pts/\d+ \(link [^)]*\): \d+ epochs written \((\d+) bytes\))"),
            ubx_bytes.size())
      << log;
  EXPECT_EQ(number_in(log, R"(receiver 0: /dev/pts/\d+ \(link [^)]*\): .*; 1 replies to the client \((\d+) bytes\))"), 10u)
      << log;

  // Receiver 1: one GGA every whole second, none missing or repeated, as many as the summary says.
  const std::string nmea_text = test::read_file(nmea);
  const test::SplitResult split = test::split_sentences(nmea_text);
  EXPECT_EQ(split.invalid, 0u);
  std::vector<std::int64_t> gga_ms;
  for (const auto& s : split.sentences) {
    if (test::sentence_type(s) == "GGA") gga_ms.push_back(nmea_ms_of_day(test::time_field(s)));
  }
  ASSERT_EQ(gga_ms.size(), static_cast<std::size_t>(duration_s)) << nmea_text;
  for (std::size_t k = 0; k < gga_ms.size(); ++k) {
    EXPECT_EQ(gga_ms[k] % 1000, 0) << "GGA " << k << " on the whole second";
    if (k > 0) {
      EXPECT_EQ((gga_ms[k] - gga_ms[k - 1] + 86'400'000) % 86'400'000, 1000) << "GGA " << k;
    }
  }
  EXPECT_EQ(number_in(log, R"(receiver 1: (\d+) epochs \(0 without fix\))"), gga_ms.size()) << log;
  EXPECT_EQ(number_in(log, "receiver 1: file " + nmea.string() + R"(: (\d+) epochs written)"), gga_ms.size()) << log;
  EXPECT_EQ(number_in(log, "receiver 1: file " + nmea.string() + R"(: \d+ epochs written \((\d+) bytes\))"),
            nmea_text.size())
      << log;
}

}  // namespace ubx_rate_test
}  // namespace
}  // namespace gpsemu
