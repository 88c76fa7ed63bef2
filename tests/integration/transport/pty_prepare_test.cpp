// PtyOutput::prepare_epoch() (called ahead of the deadline when many receivers share a process):
// it discards what no client read, so the write at the deadline is one write() and a client
// still gets only the newest epoch, whole. Against a real pseudo-terminal, waiting with poll().
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <string>

#include "transport/pty_output.hpp"

namespace gpsemu::transport {
namespace {
namespace pty_prepare_test {

/// Everything the client can read within `timeout` of the first byte (poll() with a timeout).
std::string read_available(int fd, std::chrono::milliseconds timeout) {
  std::string got;
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return got;
    char buf[4096];
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n <= 0) return got;
    got.append(buf, static_cast<std::size_t>(n));
    timeout = std::chrono::milliseconds(100);  // the rest of an epoch follows at once
  }
}

TEST(PtyPrepare, PreparedWriteDeliversOnlyTheNewestEpochAndCountsTheDiscard) {
  PtyOutput out;
  const int client = ::open(out.device_path().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  ASSERT_GE(client, 0);
  termios tio{};
  ASSERT_EQ(::tcgetattr(client, &tio), 0);
  ::cfmakeraw(&tio);
  ASSERT_EQ(::tcsetattr(client, TCSANOW, &tio), 0);

  const std::string stale = "$GPGGA,120000.00,STALE*00\r\n";
  const std::string fresh = "$GPGGA,120000.10,FRESH*00\r\n";
  ASSERT_EQ(out.write_epoch(stale), WriteStatus::ok);
  // The client does not read the first epoch; wait until it is queued on the client's side.
  pollfd p{client, POLLIN, 0};
  ASSERT_EQ(::poll(&p, 1, 2000), 1);
  out.prepare_epoch();
  EXPECT_EQ(out.pty_stats().stale_epochs_discarded, 1u);
  EXPECT_EQ(out.pty_stats().stale_bytes_discarded, stale.size());
  ASSERT_EQ(out.write_epoch(fresh), WriteStatus::ok);
  EXPECT_EQ(read_available(client, std::chrono::milliseconds(2000)), fresh);
  // Without prepare_epoch(), the write discards by itself, as before.
  ASSERT_EQ(out.write_epoch(stale), WriteStatus::ok);
  ASSERT_EQ(::poll(&p, 1, 2000), 1);
  ASSERT_EQ(out.write_epoch(fresh), WriteStatus::ok);
  EXPECT_EQ(read_available(client, std::chrono::milliseconds(2000)), fresh);
  EXPECT_EQ(out.pty_stats().stale_epochs_discarded, 2u);
  EXPECT_EQ(out.stats().epochs_written, 4u);
  ::close(client);
}

}  // namespace pty_prepare_test
}  // namespace
}  // namespace gpsemu::transport
