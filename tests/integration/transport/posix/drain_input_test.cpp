// Reading a client's input within a budget (transport/posix/fd.hpp): what one call may read and
// hand on is bounded in bytes and time, and what it leaves stays in the kernel for the next call,
// in order, nothing lost. A real non-blocking socket pair; the time budget is exercised at zero
// (one piece, then stop), so nothing here depends on how fast the machine is.
#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "transport/output.hpp"
#include "transport/posix/fd.hpp"

namespace gpsemu::posix {
namespace {
namespace drain_input_test {

struct Pair {
  UniqueFd reader, writer;
  Pair() {
    int fds[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM, 0, fds) != 0) throw std::runtime_error("socketpair");
    reader.reset(fds[0]);
    writer.reset(fds[1]);
    const int big = 1 << 20;
    ::setsockopt(writer.get(), SOL_SOCKET, SO_SNDBUF, &big, sizeof big);
    ::setsockopt(reader.get(), SOL_SOCKET, SO_RCVBUF, &big, sizeof big);
    ::fcntl(reader.get(), F_SETFL, O_NONBLOCK);
  }
};

std::string pattern(std::size_t bytes) {
  std::string s(bytes, '\0');
  for (std::size_t k = 0; k < bytes; ++k) s[k] = static_cast<char>(k * 7 + k / 251);
  return s;
}

TEST(DrainInput, AByteBudgetLeavesTheRestInTheKernelInOrder) {
  Pair p;
  const std::string sent = pattern(200 * 1024);
  ASSERT_EQ(::write(p.writer.get(), sent.data(), sent.size()), static_cast<ssize_t>(sent.size()));
  std::string got;
  const auto keep = [&](std::string_view bytes) {
    EXPECT_LE(bytes.size(), 1024u) << "worked-on input comes in pieces of at most 1 KiB";
    got.append(bytes);
  };
  int calls = 0;
  for (; got.size() < sent.size() && calls < 10; ++calls) {
    const Drained d = drain_input(p.reader.get(), transport::client_input_budget, keep);
    EXPECT_LE(d.bytes, 64u * 1024u);
    if (got.size() < sent.size()) {
      EXPECT_TRUE(d.limited) << "call " << calls;
    }
  }
  // 200 KiB in 64 KiB calls: four, or more when a call's 2 ms time budget ran out first (a
  // descheduled test on a loaded machine once took five).
  EXPECT_GE(calls, 4) << "200 KiB in 64 KiB calls";
  EXPECT_EQ(got, sent);
  const Drained empty = drain_input(p.reader.get(), transport::client_input_budget, keep);
  EXPECT_EQ(empty.bytes, 0u);
  EXPECT_FALSE(empty.limited);
  EXPECT_EQ(empty.end, Drained::End::empty);
}

TEST(DrainInput, ATimeBudgetSpentStopsAfterOnePiece) {
  Pair p;
  const std::string sent = pattern(10'000);
  ASSERT_EQ(::write(p.writer.get(), sent.data(), sent.size()), static_cast<ssize_t>(sent.size()));
  std::string got;
  const InputBudget spent{.bytes = 1 << 20, .time = std::chrono::nanoseconds{0}};
  const Drained d = drain_input(p.reader.get(), spent, [&](std::string_view bytes) { got.append(bytes); });
  EXPECT_EQ(d.bytes, 1024u);
  EXPECT_TRUE(d.limited);
  // Discarded input (no consumer) is read in big pieces.
  const Drained rest = drain_input(p.reader.get(), spent);
  EXPECT_EQ(rest.bytes, 4096u);
  EXPECT_EQ(got, sent.substr(0, 1024));
}

}  // namespace drain_input_test
}  // namespace
}  // namespace gpsemu::posix
