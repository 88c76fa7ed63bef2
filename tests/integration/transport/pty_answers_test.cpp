// Answers to a pty's client (PtyOutput, a real pseudo-terminal; issue 22 points 3, 4, 8): an
// answer never discards what the client has not read yet (it reads the rest of the epoch it began,
// then the answer); what the pty cannot take waits and goes out, in order, as the client reads;
// every client closing the device ends the connection (the client input hears client_left) and
// what was queued for it is discarded and counted; input the receiver reads is not counted as
// discarded (issue 33 point 10).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include "tests/support/answering_input.hpp"
#include "tests/support/pty_client.hpp"
#include "transport/pty_output.hpp"

namespace gpsemu::transport {
namespace {
namespace pty_answers_test {

using namespace std::chrono_literals;

using Answering = test::AnsweringInput;

int open_client(const PtyOutput& out) { return test::open_raw_pty_client(out.device_path()); }

/// Reads what arrives within `quiet` of the last byte, servicing the output between reads.
std::string read_serviced(int fd, PtyOutput& out, std::size_t want, std::chrono::milliseconds timeout = 2s) {
  std::string got;
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (got.size() < want && std::chrono::steady_clock::now() < until) {
    out.service();
    out.answer_clients();
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 20) <= 0) continue;
    char buf[8192];
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n > 0) got.append(buf, static_cast<std::size_t>(n));
  }
  return got;
}

/// Services `out` as the loop does (when its descriptor is readable) until `done()`, at most 2 s.
template <class Done>
void service_until(PtyOutput& out, Done done) {
  const auto until = std::chrono::steady_clock::now() + 2s;
  while (!done() && std::chrono::steady_clock::now() < until) {
    pollfd p{out.poll_fd(), POLLIN, 0};
    (void)::poll(&p, 1, 20);
    out.service();
    out.answer_clients();
  }
}

/// Until the client input heard `writes` writes (the client's bytes crossed the pty).
void service_until_heard(PtyOutput& out, const Answering& input, std::size_t writes) {
  service_until(out, [&] { return input.writers.size() >= writes; });
}

/// A pty whose client input answers "<ANSWER>" to every write.
class PtyAnswers : public ::testing::Test {
 protected:
  PtyAnswers() { out.set_client_input(&input); }
  PtyOutput out;
  Answering input{"<ANSWER>"};
};

TEST_F(PtyAnswers, AnAnswerNeverDiscardsWhatTheClientHasNotRead) {
  const int client = open_client(out);
  ASSERT_GE(client, 0);
  const std::string epoch = "$GPRMC,120000.00,EPOCH-ONE-WITH-A-LONG-BODY*00\r\n";
  ASSERT_EQ(out.write_epoch(epoch), WriteStatus::ok);
  pollfd p{client, POLLIN, 0};
  ASSERT_EQ(::poll(&p, 1, 2000), 1);
  char head[6];
  ASSERT_EQ(::read(client, head, sizeof head), 6);
  ASSERT_EQ(::write(client, "poll", 4), 4);
  service_until_heard(out, input, 1);
  EXPECT_EQ(read_serviced(client, out, epoch.size() - 6 + 8), epoch.substr(6) + "<ANSWER>");
  EXPECT_EQ(out.stats().replies_written, 1u);
  EXPECT_EQ(out.pty_stats().stale_bytes_discarded, 0u);
  ::close(client);
}

TEST_F(PtyAnswers, InputTheReceiverReadsIsNotCountedAsDiscarded) {
  const int client = open_client(out);
  ASSERT_GE(client, 0);
  ASSERT_EQ(::write(client, "poll", 4), 4);
  service_until_heard(out, input, 1);
  EXPECT_EQ(read_serviced(client, out, 8), "<ANSWER>");
  EXPECT_EQ(out.pty_stats().input_bytes_discarded, 0u);  // the receiver read and answered it
  out.set_client_input(nullptr);                         // none reads it now: dropped, counted
  ASSERT_EQ(::write(client, "probe", 5), 5);
  service_until(out, [&] { return out.pty_stats().input_bytes_discarded != 0; });
  EXPECT_EQ(out.pty_stats().input_bytes_discarded, 5u);
  ::close(client);
}

TEST_F(PtyAnswers, WhatThePtyCannotTakeWaitsAndGoesOutInOrderAsTheClientReads) {
  // 60 000 bytes of answers: more than the pty holds (about 22 KB), less than what waits here.
  std::string answer;
  for (int i = 0; answer.size() < 60000; ++i) answer += "<answer " + std::to_string(i) + ">";
  Answering big(answer);
  out.set_client_input(&big);
  const int client = open_client(out);
  ASSERT_GE(client, 0);
  ASSERT_EQ(::write(client, "poll", 4), 4);
  service_until_heard(out, big, 1);
  const std::string epoch = "$GPRMC,120000.10,AFTER*00\r\n";
  ASSERT_EQ(out.write_epoch(epoch), WriteStatus::ok);  // behind the answer, whole
  EXPECT_EQ(read_serviced(client, out, answer.size() + epoch.size()), answer + epoch);
  EXPECT_EQ(out.stats().replies_dropped, 0u);
  ::close(client);
}

TEST_F(PtyAnswers, EveryClientClosingTheDeviceEndsTheConnection) {
  const int first = open_client(out);
  ASSERT_GE(first, 0);
  ASSERT_EQ(::write(first, "half a frame", 12), 12);
  service_until_heard(out, input, 1);
  ASSERT_EQ(out.write_epoch("$GPRMC,UNREAD*00\r\n"), WriteStatus::ok);
  // Both reach the client's side (the kernel pushes a pty's bytes in the background), unread.
  const auto landed = std::chrono::steady_clock::now() + 2s;
  for (int queued = 0; queued < 26 && std::chrono::steady_clock::now() < landed;) {
    pollfd p{first, POLLIN, 0};
    (void)::poll(&p, 1, 10);
    ::ioctl(first, FIONREAD, &queued);
  }
  ::close(first);
  service_until(out, [&] { return !input.left.empty(); });
  ASSERT_EQ(input.left.size(), 1u);
  EXPECT_EQ(input.left[0], input.writers[0]);
  EXPECT_EQ(out.pty_stats().clients_left, 1u);
  EXPECT_GT(out.pty_stats().stale_bytes_discarded, 0u) << "the unread answer and epoch";

  const int next = open_client(out);
  ASSERT_GE(next, 0);
  ASSERT_EQ(::write(next, "poll", 4), 4);
  service_until_heard(out, input, 2);
  ASSERT_EQ(input.writers.size(), 2u);
  EXPECT_NE(input.writers[1], input.writers[0]) << "a new client";
  EXPECT_EQ(read_serviced(next, out, 8), "<ANSWER>") << "nothing of the first client's";
  ::close(next);
}

}  // namespace pty_answers_test
}  // namespace
}  // namespace gpsemu::transport
