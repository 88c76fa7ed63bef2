// The POSIX layer without sockets: the descriptor owner closes exactly once and moves ownership,
// drain_input reads and discards within its limit and tells end of file, errno text, the texts
// that name addresses, resolve errors that name host:port, the wall clock and the drop counter.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <arpa/inet.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <stdexcept>
#include <string>

#include "transport/posix/errors.hpp"
#include "transport/posix/fd.hpp"
#include "transport/posix/sockets.hpp"
#include "transport/posix/wall_clock.hpp"

namespace gpsemu::posix {
namespace {
namespace posix_test {

bool is_open(int fd) { return ::fcntl(fd, F_GETFD) != -1; }

struct Pipe {
  UniqueFd read, write;
  Pipe() {
    int fds[2];
    if (::pipe2(fds, O_NONBLOCK | O_CLOEXEC) != 0) throw std::runtime_error("pipe2");
    read.reset(fds[0]);
    write.reset(fds[1]);
  }
};

TEST(UniqueFd, ClosesItsDescriptorWhenItGoes) {
  int raw = -1;
  {
    const UniqueFd fd(::open("/dev/null", O_RDONLY | O_CLOEXEC));
    raw = fd.get();
    ASSERT_TRUE(fd.valid());
    EXPECT_TRUE(is_open(raw));
  }
  EXPECT_FALSE(is_open(raw));
  EXPECT_FALSE(UniqueFd().valid());
}

TEST(UniqueFd, MoveTransfersOwnershipAndAssignmentClosesThePrevious) {
  UniqueFd a(::open("/dev/null", O_RDONLY | O_CLOEXEC));
  const int first = a.get();
  UniqueFd b(std::move(a));
  EXPECT_FALSE(a.valid());  // NOLINT(bugprone-use-after-move): moved-from is empty by contract
  EXPECT_EQ(b.get(), first);
  EXPECT_TRUE(is_open(first));

  UniqueFd c(::open("/dev/null", O_RDONLY | O_CLOEXEC));
  const int second = c.get();
  c = std::move(b);  // closes `second`, owns `first`
  EXPECT_FALSE(is_open(second));
  EXPECT_EQ(c.get(), first);
  EXPECT_TRUE(is_open(first));

  const int released = c.release();
  EXPECT_FALSE(c.valid());
  EXPECT_TRUE(is_open(released));  // the caller owns it now
  ::close(released);
}

TEST(UniqueFd, ResetClosesAndTakesTheNewOne) {
  UniqueFd fd(::open("/dev/null", O_RDONLY | O_CLOEXEC));
  const int old = fd.get();
  fd.reset(::open("/dev/null", O_RDONLY | O_CLOEXEC));
  EXPECT_TRUE(fd.valid());
  EXPECT_NE(fd.get(), -1);
  if (fd.get() != old) {
    EXPECT_FALSE(is_open(old));
  }
  fd.reset();
  EXPECT_FALSE(fd.valid());
}

TEST(DrainInput, DiscardsWhatWaitsThenSaysEmptyOrClosed) {
  Pipe p;
  const std::string probe(10000, 'x');
  ASSERT_EQ(::write(p.write.get(), probe.data(), probe.size()), static_cast<ssize_t>(probe.size()));
  Drained d = drain_input(p.read.get(), 1 << 20);
  EXPECT_EQ(d.bytes, probe.size());
  EXPECT_EQ(d.end, Drained::End::empty);
  d = drain_input(p.read.get(), 1 << 20);
  EXPECT_EQ(d.bytes, 0u);
  EXPECT_EQ(d.end, Drained::End::empty);
  ASSERT_EQ(::write(p.write.get(), "abc", 3), 3);
  p.write.reset();
  d = drain_input(p.read.get(), 1 << 20);
  EXPECT_EQ(d.bytes, 3u);
  EXPECT_EQ(d.end, Drained::End::closed);
}

TEST(DrainInput, StopsAtItsLimitAndLeavesTheRest) {
  Pipe p;
  const std::string probe(12000, 'x');
  ASSERT_EQ(::write(p.write.get(), probe.data(), probe.size()), static_cast<ssize_t>(probe.size()));
  const Drained first = drain_input(p.read.get(), 4096);
  EXPECT_EQ(first.bytes, 4096u);  // one read of its 4096-byte buffer reaches the limit
  EXPECT_EQ(first.end, Drained::End::empty);
  EXPECT_EQ(drain_input(p.read.get(), 1 << 20).bytes, probe.size() - 4096);
}

TEST(DrainInput, ABadDescriptorIsAFailureWithItsErrno) {
  const Drained d = drain_input(-1, 100);
  EXPECT_EQ(d.end, Drained::End::failed);
  EXPECT_EQ(d.error, EBADF);
}

TEST(ErrnoText, IsTheSystemsText) {
  EXPECT_EQ(errno_text(ENOENT), "No such file or directory");
  EXPECT_EQ(errno_text(EADDRINUSE), "Address already in use");
}

TEST(Endpoint, ParsesHostPortWithTheLoopbackByDefaultAndReadsBack) {
  EXPECT_EQ(parse_endpoint("5005").host, "127.0.0.1");
  EXPECT_EQ(parse_endpoint("5005").port, 5005);
  const Endpoint v6 = parse_endpoint("[::1]:7000");
  EXPECT_EQ(host_port(v6.host, v6.port), "[::1]:7000");
  for (const char* bad : {"", ":5", "x:", "::1:7000", "[::1]7000", "host:70000", "host:-1"}) {
    EXPECT_THROW((void)parse_endpoint(bad), std::invalid_argument) << bad;
  }
}

TEST(AddressText, HostPortBracketsIpv6) {
  EXPECT_EQ(host_port("127.0.0.1", 5005), "127.0.0.1:5005");
  EXPECT_EQ(host_port("gps.local", 0), "gps.local:0");
  EXPECT_EQ(host_port("::1", 10110), "[::1]:10110");
}

TEST(AddressText, FormatsIpv4Ipv6AndCutsToFit) {
  sockaddr_storage v4{};
  auto* a = reinterpret_cast<sockaddr_in*>(&v4);
  a->sin_family = AF_INET;
  a->sin_port = htons(50123);
  ::inet_pton(AF_INET, "203.0.113.5", &a->sin_addr);
  EXPECT_EQ(address_text(v4), "203.0.113.5:50123");
  std::array<char, 6> small{};
  EXPECT_EQ(std::string(small.data(), format_address(v4, small)), "203.0.");  // the 6 bytes that fit

  sockaddr_storage v6{};
  auto* b = reinterpret_cast<sockaddr_in6*>(&v6);
  b->sin6_family = AF_INET6;
  b->sin6_port = htons(7);
  ::inet_pton(AF_INET6, "::1", &b->sin6_addr);
  EXPECT_EQ(address_text(v6), "[::1]:7");

  EXPECT_EQ(address_text(sockaddr_storage{}), "?");
}

TEST(OpenSocket, AnUnknownHostIsNamedWithItsPort) {
  const SocketRequest request{.host = "no-such-host.invalid", .port = 5005,
                              .context = "cannot listen on tcp:" + host_port("no-such-host.invalid", 5005)};
  try {
    (void)listen_tcp(request);
    FAIL() << "listened on an unknown host";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("cannot listen on tcp:no-such-host.invalid:5005: host 'no-such-host.invalid': ", 0), 0u)
        << what;
  }
  try {
    (void)connect_socket({.host = "no-such-host.invalid", .port = 10110, .type = SOCK_DGRAM,
                          .context = "udp output udp:no-such-host.invalid:10110"});
    FAIL() << "connected to an unknown host";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("udp:no-such-host.invalid:10110: host 'no-such-host.invalid'"),
              std::string::npos)
        << e.what();
  }
}

TEST(WallClock, IsTheSystemClockInNanoseconds) {
  const auto before = std::chrono::system_clock::now();
  const WallTime now = wall_clock_now();
  const auto after = std::chrono::system_clock::now();
  EXPECT_GE(now, std::chrono::time_point_cast<std::chrono::nanoseconds>(before));
  EXPECT_LE(now, std::chrono::time_point_cast<std::chrono::nanoseconds>(after));
  EXPECT_EQ(to_wall_time(timespec{1, 500}).time_since_epoch(), std::chrono::nanoseconds{1'000'000'500});
  EXPECT_DOUBLE_EQ(to_unix_seconds(to_wall_time(timespec{2, 250'000'000})), 2.25);
}

TEST(DropCounter, CountsSinceLastSeenAcrossTheWrap) {
  DropCounter drops;
  EXPECT_EQ(drops.update(5), 5u);
  EXPECT_EQ(drops.update(7), 2u);
  EXPECT_EQ(drops.update(7), 0u);
  EXPECT_EQ(drops.update(0xFFFFFFFEu), 0xFFFFFFFEu - 7u);
  EXPECT_EQ(drops.update(1), 3u);  // the kernel's 32-bit counter wrapped
}

}  // namespace posix_test
}  // namespace
}  // namespace gpsemu::posix
