// PtyOutput against real pseudo-terminals: a client opens the device (or its link) the way gpsd
// does and the tests assert on the bytes it reads. Waiting is always poll() with a timeout.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "tests/support/nmea_check.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"
#include "transport/pty_output.hpp"

namespace gpsemu::transport {
namespace {
namespace pty_test {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  Fd(Fd&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  Fd& operator=(Fd&& other) noexcept {
    std::swap(fd_, other.fd_);
    return *this;
  }
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  [[nodiscard]] int get() const { return fd_; }

 private:
  int fd_;
};

/// Opens the device as gpsd does: read-write, not as controlling terminal, raw, non-blocking.
Fd open_client(const fs::path& path) {
  Fd fd(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK));
  EXPECT_GE(fd.get(), 0) << "open " << path;
  termios tio{};
  EXPECT_EQ(::tcgetattr(fd.get(), &tio), 0);
  ::cfmakeraw(&tio);
  EXPECT_EQ(::tcsetattr(fd.get(), TCSANOW, &tio), 0);
  return fd;
}

/// Reads until `want` bytes arrived or `timeout` passed; a failed read is a test failure.
std::string read_exactly(int fd, std::size_t want, std::chrono::milliseconds timeout = 2s) {
  const test::ReadResult r = test::read_with_deadline(fd, {timeout, std::nullopt, want});
  EXPECT_EQ(r.error, 0) << "read: " << std::strerror(r.error);
  return r.bytes;
}

/// Reads everything that arrives until nothing more comes for `quiet`.
std::string read_until_quiet(int fd, std::chrono::milliseconds quiet = 200ms) {
  return test::read_available(fd, quiet, 60s);
}

using test::epoch;

class PtyOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (test::scratch_root() / "gpsemu_pty_XXXXXX").string();
    ASSERT_NE(::mkdtemp(templ.data()), nullptr);
    dir_ = templ;
    link_ = dir_ / "gpsemu";
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  fs::path link_;
};

TEST_F(PtyOutputTest, ClientReadsEachEpochInOrderThroughLink) {
  PtyOutput pty(link_);
  Fd client = open_client(link_);
  std::string expected;
  std::string received;
  // Real time: each epoch is read before the next one is due (an unread one would be discarded).
  for (int k = 0; k < 10; ++k) {
    const std::string e = epoch(k);
    ASSERT_EQ(pty.write_epoch(e), WriteStatus::ok);
    expected += e;
    received += read_exactly(client.get(), e.size());
  }
  EXPECT_EQ(received, expected);
  EXPECT_EQ(read_until_quiet(client.get(), 50ms), "");
  EXPECT_EQ(pty.stats().epochs_written, 10u);
  EXPECT_EQ(pty.stats().bytes_written, expected.size());
  EXPECT_EQ(pty.pty_stats().stale_bytes_discarded, 0u);
}

TEST_F(PtyOutputTest, ServiceDrainsClientGarbageWithoutBlocking) {
  PtyOutput pty(link_);
  Fd client = open_client(link_);
  std::string garbage(64 * 1024, '\0');
  unsigned x = 12345;
  for (char& c : garbage) c = static_cast<char>((x = x * 1103515245u + 12345u) >> 16);

  std::size_t sent = 0;
  bool changed_speed = false;
  const auto deadline = Clock::now() + 10s;
  while (pty.pty_stats().input_bytes_discarded < garbage.size()) {
    ASSERT_LT(Clock::now(), deadline) << "sent " << sent << ", drained "
                                      << pty.pty_stats().input_bytes_discarded;
    if (sent < garbage.size()) {
      const ssize_t n = ::write(client.get(), garbage.data() + sent,
                                std::min<std::size_t>(4096, garbage.size() - sent));
      if (n > 0) sent += static_cast<std::size_t>(n);
      ASSERT_TRUE(n > 0 || errno == EAGAIN) << std::strerror(errno);
    }
    if (!changed_speed && sent > garbage.size() / 2) {
      // gpsd hunts for the baud rate while probing.
      termios tio{};
      ASSERT_EQ(::tcgetattr(client.get(), &tio), 0);
      ::cfsetspeed(&tio, B4800);
      ASSERT_EQ(::tcsetattr(client.get(), TCSANOW, &tio), 0);
      ::cfsetspeed(&tio, B115200);
      ASSERT_EQ(::tcsetattr(client.get(), TCSANOW, &tio), 0);
      changed_speed = true;
    }
    pollfd fds[2] = {{pty.poll_fd(), POLLIN, 0},
                     {client.get(), static_cast<short>(sent < garbage.size() ? POLLOUT : 0), 0}};
    ASSERT_GE(::poll(fds, 2, 100), 0);
    pty.service();
  }
  EXPECT_EQ(sent, garbage.size());
  EXPECT_EQ(pty.pty_stats().input_bytes_discarded, garbage.size());

  for (int k = 0; k < 3; ++k) {
    const std::string e = epoch(k);
    ASSERT_EQ(pty.write_epoch(e), WriteStatus::ok);
    EXPECT_EQ(read_exactly(client.get(), e.size()), e);
  }
  pty.service();  // nothing to read: returns at once
  EXPECT_EQ(pty.pty_stats().input_bytes_discarded, garbage.size());
}

TEST_F(PtyOutputTest, ClientClosingAndReopeningTwentyTimesKeepsReceiving) {
  PtyOutput pty(link_);
  for (int i = 0; i < 20; ++i) {
    // Written while no client has the device open: must not fail, must not reach the next one.
    ASSERT_EQ(pty.write_epoch(epoch(1000 + i)), WriteStatus::ok);
    Fd client = open_client(link_);
    const std::string e = epoch(i);
    ASSERT_EQ(pty.write_epoch(e), WriteStatus::ok);
    ASSERT_EQ(read_exactly(client.get(), e.size()), e) << "reopen " << i;
    client = Fd();
    pollfd pfd{pty.poll_fd(), POLLIN, 0};
    ASSERT_GE(::poll(&pfd, 1, 0), 0);
    EXPECT_EQ(pfd.revents & (POLLHUP | POLLERR), 0) << "master hung up after close " << i;
    pty.service();
  }
  EXPECT_EQ(pty.stats().epochs_written, 40u);
  EXPECT_EQ(pty.stats().epochs_failed, 0u);
  EXPECT_EQ(pty.stats().epochs_dropped, 0u);
}

TEST_F(PtyOutputTest, LateClientSeesOnlyNewestEpochAndStaleOnesAreCounted) {
  PtyOutput pty(link_);
  // A descriptor that has the device open but never reads, like the emulator's own slave side
  // (so this is still "no client"). Waiting on it with poll() makes sure each epoch has reached
  // the slave's queue before the next one is written, so the discard counts are exact.
  Fd holder(::open(pty.device_path().c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK));
  ASSERT_GE(holder.get(), 0);
  std::size_t older_bytes = 0;
  for (int k = 0; k < 10; ++k) {
    ASSERT_EQ(pty.write_epoch(epoch(k)), WriteStatus::ok);
    pollfd pfd{holder.get(), POLLIN, 0};
    ASSERT_EQ(::poll(&pfd, 1, 2000), 1);
    if (k < 9) older_bytes += epoch(k).size();
  }
  EXPECT_EQ(pty.pty_stats().stale_epochs_discarded, 9u);
  EXPECT_EQ(pty.pty_stats().stale_bytes_discarded, older_bytes);

  Fd client = open_client(link_);
  const std::string backlog = read_until_quiet(client.get());
  EXPECT_TRUE(backlog.empty() || backlog == epoch(9)) << backlog;
  ASSERT_EQ(pty.write_epoch(epoch(10)), WriteStatus::ok);
  EXPECT_EQ(read_exactly(client.get(), epoch(10).size()), epoch(10));
}

TEST_F(PtyOutputTest, LateClientAfterBurstNeverSeesOlderEpochs) {
  PtyOutput pty(link_);
  for (int k = 0; k < 10; ++k) ASSERT_EQ(pty.write_epoch(epoch(k)), WriteStatus::ok);
  Fd client = open_client(link_);
  const std::string backlog = read_until_quiet(client.get());
  EXPECT_TRUE(backlog.empty() || backlog == epoch(9)) << backlog;
  ASSERT_EQ(pty.write_epoch(epoch(10)), WriteStatus::ok);
  EXPECT_EQ(read_exactly(client.get(), epoch(10).size()), epoch(10));
  EXPECT_EQ(read_until_quiet(client.get(), 50ms), "");
}

TEST_F(PtyOutputTest, WithoutLinkDescribesTheDevice) {
  PtyOutput pty;
  EXPECT_FALSE(pty.link_path().has_value());
  EXPECT_TRUE(fs::is_character_file(pty.device_path())) << pty.device_path();
  EXPECT_EQ(pty.describe(), pty.device_path().string());
  EXPECT_GE(pty.poll_fd(), 0);
}

TEST_F(PtyOutputTest, SymlinkPointsToDeviceAndIsRemovedOnDestruction) {
  fs::path device;
  {
    PtyOutput pty(link_);
    device = pty.device_path();
    ASSERT_TRUE(fs::is_symlink(link_));
    EXPECT_EQ(fs::read_symlink(link_), device);
    EXPECT_EQ(pty.link_path(), link_);
    EXPECT_EQ(pty.describe(), device.string() + " (link " + link_.string() + ")");
  }
  EXPECT_FALSE(fs::exists(fs::symlink_status(link_)));
}

void expect_runtime_error_naming(const fs::path& link, const std::string& text) {
  try {
    PtyOutput pty(link);
    ADD_FAILURE() << "no exception for " << link;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

TEST_F(PtyOutputTest, RegularFileAtLinkThrowsNamingPathAndIsKept) {
  std::ofstream(link_) << "precious";
  expect_runtime_error_naming(link_, link_.string());
  std::ifstream in(link_);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "precious");
}

TEST_F(PtyOutputTest, MissingLinkDirectoryThrowsNamingPath) {
  expect_runtime_error_naming(dir_ / "no-such-dir" / "gpsemu", (dir_ / "no-such-dir").string());
}

TEST_F(PtyOutputTest, StaleSymlinkIsReplaced) {
  fs::create_symlink("/dev/pts/does-not-exist", link_);
  {
    PtyOutput pty(link_);
    EXPECT_EQ(fs::read_symlink(link_), pty.device_path());
    Fd client = open_client(link_);
    ASSERT_EQ(pty.write_epoch(epoch(0)), WriteStatus::ok);
    EXPECT_EQ(read_exactly(client.get(), epoch(0).size()), epoch(0));
  }
  EXPECT_FALSE(fs::exists(fs::symlink_status(link_)));
}

TEST_F(PtyOutputTest, LinkTakenOverByAnotherRunIsLeftAlone) {
  std::optional<PtyOutput> first(std::in_place, link_);
  PtyOutput second;  // another run's pty, to which the link is moved while the first still runs
  fs::remove(link_);
  fs::create_symlink(second.device_path(), link_);
  first.reset();  // the first run ends: the link is not its own any more, so it stays
  ASSERT_TRUE(fs::is_symlink(link_));
  EXPECT_EQ(fs::read_symlink(link_), second.device_path());
}

TEST_F(PtyOutputTest, LinkOfALivePtyServingItIsRefusedAndFreedWhenItEnds) {
  std::optional<PtyOutput> first(std::in_place, link_);
  try {
    PtyOutput second(link_);
    ADD_FAILURE() << "a second pty took over the link of a live one";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(link_.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("still running"), std::string::npos) << e.what();
  }
  EXPECT_EQ(fs::read_symlink(link_), first->device_path());  // untouched
  // A pty serving another link does not hold this one.
  const fs::path other = dir_ / "other";
  PtyOutput unrelated(other);
  first.reset();
  PtyOutput third(link_);
  EXPECT_EQ(fs::read_symlink(link_), third.device_path());
}

}  // namespace pty_test
}  // namespace
}  // namespace gpsemu::transport
