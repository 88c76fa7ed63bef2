// A u-blox client changes the receiver's epoch rate and its line's speed, end to end on the gpsemu
// binary: on a real pty at --rate 1, CFG-RATE 200 ms then 100 ms is acknowledged and NAV-PVT
// follows (iTOW on the new grid, the count per second too), 50 ms on an M8N gives its fastest
// 10 Hz, 1000 ms brings 1 Hz back; on a serial line (socat pty pair) switched to 9600 baud at
// 10 Hz, the TX buffer drops whole messages only and the summary counts them. The start-up lines
// say what a u-blox receiver writes and its widest epoch with the UBX bytes.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/socat_pair.hpp"

namespace gpsemu {
namespace {

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

  void read(int fd, milliseconds how_long) {
    (void)test::read_with_deadline(fd, {how_long}, [&](std::string_view bytes) {
      for (auto& m : reader.feed(bytes)) {
        if (auto* f = std::get_if<ubx::Frame>(&m)) {
          frames.push_back(std::move(*f));
        } else {
          ++sentences;
        }
      }
      return false;
    });
  }
  /// iTOW of each NAV-PVT from frame `from` on.
  [[nodiscard]] std::vector<std::uint32_t> pvt_itow(std::size_t from = 0) const {
    std::vector<std::uint32_t> out;
    for (std::size_t k = from; k < frames.size(); ++k) {
      if (frames[k].id == ubx::msg::nav_pvt) out.push_back(ubx::get_u4(frames[k].payload, 0));
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
  EXPECT_NE(log.find("u-blox CFG-RATE: a solution every 200 ms"), std::string::npos) << log;
  EXPECT_NE(log.find("navigates at most every 100 ms"), std::string::npos) << log;
}

TEST(UbxRate, ABaudTooSlowForTheEpochDropsWholeMessagesAndTheSummaryCountsThem) {
  const auto dir = test::scratch_dir("ubx_rate", "baud");
  test::SocatPair pair(dir / "A", dir / "B");
  const int fd = test::open_raw(pair.b());
  test::Process gpsemu({GPSEMU_BINARY, "--protocol", "nmea+ubx", "--receiver", "ublox-m8n", "--rate", "10",
                        "--output", "serial:" + pair.a().string() + "@115200", "--duration", "5", "--log-level",
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

}  // namespace
}  // namespace gpsemu
