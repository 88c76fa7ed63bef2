// A u-blox's answers, end to end on the gpsemu binary (issue 22 points 3, 4 and 8):
// - on a real pty, a client that has read the first 6 bytes of a NAV-PVT and then writes a poll
//   reads the whole NAV-PVT, then the answer: an answer never discards what the client has not
//   read (5 times);
// - 1000 CFG-RATE polls in one write get 1000 answers and 1000 ACK-ACKs, whole;
// - over TCP each connection is a client of its own: polls written half by half by two clients
//   at once are each answered, to the client that asked only; a client that disconnects in the
//   middle of a frame (its header announcing 1000 bytes) leaves nothing behind for the next one;
// - on a pty, a client that closes the device in the middle of a frame leaves nothing behind for
//   the next one to open it.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/process.hpp"
#include "tests/support/pty_client.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace ubx_replies_test {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

const std::string kRatePoll = ubx::frame_bytes(ubx::msg::cfg_rate, "");
const std::string kMonVerPoll = ubx::frame_bytes(ubx::msg::mon_ver, "");

/// What a client read: its frames in order, and the reader's counts (checksums checked).
struct Heard {
  ubx::FrameReader reader;
  std::vector<ubx::Frame> frames;
  void feed(std::string_view bytes) {
    for (auto& m : reader.feed(bytes)) {
      if (auto* f = std::get_if<ubx::Frame>(&m)) frames.push_back(std::move(*f));
    }
  }
  [[nodiscard]] std::size_t count(ubx::MessageId id) const {
    std::size_t n = 0;
    for (const auto& f : frames) n += f.id == id ? 1 : 0;
    return n;
  }
  [[nodiscard]] std::size_t acks_of(ubx::MessageId id) const {
    std::size_t n = 0;
    for (const auto& f : frames) {
      n += f.id == ubx::msg::ack_ack && f.payload.size() == 2 && static_cast<std::uint8_t>(f.payload[0]) == id.msg_class &&
                   static_cast<std::uint8_t>(f.payload[1]) == id.msg_id
               ? 1
               : 0;
    }
    return n;
  }
};

/// Writes all of `bytes` to the non-blocking `fd`, waiting for room with poll().
bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n > 0) {
      bytes.remove_prefix(static_cast<std::size_t>(n));
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EINTR) return false;
    pollfd p{fd, POLLOUT, 0};
    if (::poll(&p, 1, 2000) <= 0) return false;
  }
  return true;
}

/// Reads one byte at a time until the bytes read end with `prefix`; false after `timeout`.
bool read_up_to(int fd, const std::string& prefix, std::chrono::milliseconds timeout) {
  std::string got;
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    char c = 0;
    if (::read(fd, &c, 1) != 1) continue;
    got.push_back(c);
    if (got.size() >= prefix.size() && got.compare(got.size() - prefix.size(), prefix.size(), prefix) == 0) return true;
  }
  return false;
}

void read_into(int fd, Heard& heard, std::chrono::milliseconds how_long) {
  (void)test::read_with_deadline(fd, {how_long}, [&](std::string_view bytes) {
    heard.feed(bytes);
    return false;
  });
}

fs::path scratch_link(const std::string& name) {
  return test::scratch_root() / name;
}

/// gpsemu as a u-blox M8N at 5 Hz on `output`, once it says so ("UBX on ...": the line returned).
std::unique_ptr<test::Process> start_ublox(const std::string& output, std::string& opened) {
  auto gpsemu = std::make_unique<test::Process>(std::vector<std::string>{
      GPSEMU_BINARY, "--protocol", "ubx", "--receiver", "ublox-m8n", "--rate", "5", "--output", output, "--log-level", "info"});
  opened = gpsemu->wait_for_stderr("UBX on ", 10s).value_or("");
  return gpsemu;
}

/// Stops gpsemu with SIGTERM: exit status 0.
void stop(test::Process& gpsemu) {
  gpsemu.signal(SIGTERM);
  EXPECT_EQ(gpsemu.wait(10s), 0) << gpsemu.stderr_text();
}

/// gpsemu as a u-blox on a pty link (started before each test, stopped after it).
class UbxRepliesOnPty : public ::testing::Test {
 protected:
  void SetUp() override {
    gpsemu = start_ublox("pty:" + link.string(), opened);
    ASSERT_NE(opened, "") << gpsemu->stderr_text();
  }
  void TearDown() override { stop(*gpsemu); }

  const fs::path link = scratch_link(::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::string opened;
  std::unique_ptr<test::Process> gpsemu;
};

TEST_F(UbxRepliesOnPty, AnAnswerNeverCutsTheNavPvtTheClientIsReading) {
  const int fd = test::open_raw_pty_client(link);
  ASSERT_GE(fd, 0);
  const std::string pvt_head("\xb5\x62\x01\x07\x5c\x00", 6);  // NAV-PVT, 92 bytes of payload
  for (int round = 0; round < 5; ++round) {
    ASSERT_TRUE(read_up_to(fd, pvt_head, 3s)) << "round " << round << "\n" << gpsemu->stderr_text();
    ASSERT_TRUE(write_all(fd, kRatePoll));
    // The client reads on after the answer has been written (well within the 200 ms to the next
    // epoch): the rest of the NAV-PVT must still be there, before the answer.
    std::this_thread::sleep_for(60ms);
    Heard heard;
    heard.feed(pvt_head);
    read_into(fd, heard, 100ms);
    ASSERT_GE(heard.frames.size(), 3u) << "round " << round;
    EXPECT_EQ(heard.frames[0].id, ubx::msg::nav_pvt) << "round " << round << ": the NAV-PVT begun was cut";
    EXPECT_EQ(heard.reader.stats().bad_checksum, 0u) << "round " << round;
    EXPECT_EQ(heard.reader.stats().garbage_bytes, 0u) << "round " << round;
    EXPECT_EQ(heard.count(ubx::msg::cfg_rate), 1u) << "round " << round;
    EXPECT_EQ(heard.acks_of(ubx::msg::cfg_rate), 1u) << "round " << round;
  }
  ::close(fd);
}

TEST_F(UbxRepliesOnPty, AThousandPollsInOneWriteGetAThousandAnswers) {
  const int fd = test::open_raw_pty_client(link);
  ASSERT_GE(fd, 0);
  std::string polls;
  for (int i = 0; i < 1000; ++i) polls += kRatePoll;
  Heard heard;
  ASSERT_TRUE(write_all(fd, polls));
  // Read until every answer came (or 5 s).
  (void)test::read_with_deadline(fd, {5s}, [&](std::string_view bytes) {
    heard.feed(bytes);
    return heard.acks_of(ubx::msg::cfg_rate) >= 1000;
  });
  EXPECT_EQ(heard.count(ubx::msg::cfg_rate), 1000u);
  EXPECT_EQ(heard.acks_of(ubx::msg::cfg_rate), 1000u);
  EXPECT_EQ(heard.reader.stats().bad_checksum, 0u);
  ::close(fd);
  std::printf("1000 CFG-RATE polls in one write (%zu bytes): %zu answers, %zu ACK-ACKs\n", polls.size(),
              heard.count(ubx::msg::cfg_rate), heard.acks_of(ubx::msg::cfg_rate));
}

// Past the limits (64 KiB of answers waiting for a client) nothing is dropped silently: every one
// of 5000 polls in one write (120 000 bytes of answers) is answered or counted in the summary.
TEST_F(UbxRepliesOnPty, FiveThousandPollsAreEachAnsweredOrCounted) {
  const int fd = test::open_raw_pty_client(link);
  ASSERT_GE(fd, 0);
  std::string polls;
  for (int i = 0; i < 5000; ++i) polls += kRatePoll;
  ASSERT_TRUE(write_all(fd, polls));
  Heard heard;
  (void)test::read_with_deadline(fd, {3s}, [&](std::string_view bytes) {
    heard.feed(bytes);
    return false;
  });
  ::close(fd);
  stop(*gpsemu);
  std::smatch m;
  const std::string err = gpsemu->stderr_text();
  std::uint64_t dropped_bytes = 0;
  if (std::regex_search(err, m, std::regex("answers to clients: [0-9]+ batches written, [0-9]+ dropped whole \\(([0-9]+) bytes"))) {
    dropped_bytes = std::stoull(m[1]);
  }
  const std::size_t answered = heard.acks_of(ubx::msg::cfg_rate);
  EXPECT_EQ(heard.count(ubx::msg::cfg_rate), answered) << "an answer without its ACK, or the reverse";
  EXPECT_EQ(dropped_bytes % 24, 0u) << "dropped whole: an answer and its ACK are 24 bytes";
  EXPECT_EQ(answered + dropped_bytes / 24, 5000u) << err;
  EXPECT_GE(answered, 1000u);
  EXPECT_EQ(heard.reader.stats().bad_checksum, 0u);
  std::printf("5000 CFG-RATE polls in one write: %zu answered, %llu dropped whole and counted\n", answered,
              static_cast<unsigned long long>(dropped_bytes / 24));
}

TEST(UbxRepliesOverTcp, EachTcpClientHasItsOwnReaderAndItsOwnAnswers) {
  std::string opened;
  const auto gpsemu = start_ublox("tcp:127.0.0.1:0", opened);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(opened, m, std::regex("tcp:127\\.0\\.0\\.1:([0-9]+)"))) << gpsemu->stderr_text();
  const auto port = static_cast<std::uint16_t>(std::stoi(m[1]));

  // A client that disconnects in the middle of a frame whose header announces 1000 bytes.
  const int gone = test::tcp_to(port);
  ASSERT_GE(gone, 0);
  ASSERT_TRUE(write_all(gone, std::string("\xb5\x62\x06\x01\xe8\x03\x01\x02\x03", 9)));
  std::this_thread::sleep_for(200ms);
  ::close(gone);

  const int a = test::tcp_to(port);
  const int b = test::tcp_to(port);
  ASSERT_GE(a, 0);
  ASSERT_GE(b, 0);
  std::this_thread::sleep_for(200ms);  // both accepted
  // Interleaved halves: a's MON-VER poll and b's CFG-RATE poll, each split in two.
  ASSERT_TRUE(write_all(a, kMonVerPoll.substr(0, 3)));
  std::this_thread::sleep_for(50ms);
  ASSERT_TRUE(write_all(b, kRatePoll.substr(0, 3)));
  std::this_thread::sleep_for(50ms);
  ASSERT_TRUE(write_all(a, kMonVerPoll.substr(3)));
  std::this_thread::sleep_for(50ms);
  ASSERT_TRUE(write_all(b, kRatePoll.substr(3)));
  Heard heard_a, heard_b;
  read_into(a, heard_a, 600ms);
  read_into(b, heard_b, 600ms);
  EXPECT_EQ(heard_a.count(ubx::msg::mon_ver), 1u) << "a's MON-VER poll answered to a";
  EXPECT_EQ(heard_a.count(ubx::msg::cfg_rate), 0u) << "b's answer went to a too";
  EXPECT_EQ(heard_a.acks_of(ubx::msg::cfg_rate), 0u);
  EXPECT_EQ(heard_b.count(ubx::msg::cfg_rate), 1u) << "b's CFG-RATE poll answered to b";
  EXPECT_EQ(heard_b.acks_of(ubx::msg::cfg_rate), 1u);
  EXPECT_EQ(heard_b.count(ubx::msg::mon_ver), 0u) << "a's answer went to b too";
  // Both still get every epoch.
  EXPECT_GE(heard_a.count(ubx::msg::nav_pvt), 2u);
  EXPECT_GE(heard_b.count(ubx::msg::nav_pvt), 2u);
  ::close(a);
  ::close(b);
  stop(*gpsemu);
}

TEST_F(UbxRepliesOnPty, APtyClientClosingInTheMiddleOfAFrameLeavesNothingForTheNext) {
  for (int round = 0; round < 3; ++round) {
    const int gone = test::open_raw_pty_client(link);
    ASSERT_GE(gone, 0);
    ASSERT_TRUE(write_all(gone, std::string("\xb5\x62\x06\x01\xe8\x03\x01\x02\x03", 9)));
    std::this_thread::sleep_for(200ms);
    ::close(gone);
    std::this_thread::sleep_for(100ms);
    const int next = test::open_raw_pty_client(link);
    ASSERT_GE(next, 0);
    ASSERT_TRUE(write_all(next, kMonVerPoll));
    Heard heard;
    (void)test::read_with_deadline(next, {1s}, [&](std::string_view bytes) {
      heard.feed(bytes);
      return heard.count(ubx::msg::mon_ver) > 0;
    });
    EXPECT_EQ(heard.count(ubx::msg::mon_ver), 1u) << "round " << round << ": the next client's poll was not answered";
    ::close(next);
  }
}

}  // namespace ubx_replies_test
}  // namespace
}  // namespace gpsemu
