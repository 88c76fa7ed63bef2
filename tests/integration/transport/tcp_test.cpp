// TCP output with real sockets on loopback: clients receive whole epochs from the first one after
// they connect; a client that stops reading is disconnected without delaying the others or the
// writer; client input is discarded; each connection is a client of its own (an answer goes to the
// client that asked, a disconnect is told to the client input); specs and start-up errors.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/support/answering_input.hpp"
#include "tests/support/nmea_check.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"
#include "transport/output_spec.hpp"
#include "transport/tcp_output.hpp"

namespace gpsemu::transport {
namespace {
namespace tcp_test {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

using test::epoch;

/// A client socket connected to 127.0.0.1:port; `receive_buffer` > 0 shrinks SO_RCVBUF first.
int connect_client(std::uint16_t port, int receive_buffer = 0) {
  const int fd = test::tcp_to(port, receive_buffer);
  if (fd < 0) throw std::runtime_error("connect failed");
  return fd;
}

/// Services the server (polling its one descriptor, as the runner does) until `done` or timeout.
template <class Done>
bool service_until(TcpOutput& out, Done done, std::chrono::milliseconds timeout = 5s) {
  const auto deadline = Clock::now() + timeout;
  while (!done()) {
    if (Clock::now() > deadline) return false;
    pollfd pfd{out.poll_fd(), POLLIN, 0};
    (void)::poll(&pfd, 1, 10);
    out.service();
  }
  return true;
}

using test::read_exactly;

TEST(TcpOutputTest, EachConnectionIsAClientOfItsOwn) {
  TcpOutput out("127.0.0.1", 0);
  test::AnsweringInput input("<ANSWER>");
  out.set_client_input(&input);
  const int asker = connect_client(out.port());
  const int other = connect_client(out.port());
  ASSERT_TRUE(service_until(out, [&] { return out.client_count() == 2; }));
  ASSERT_EQ(::write(asker, "poll", 4), 4);
  ASSERT_TRUE(service_until(out, [&] { return input.writers.size() == 1; }));
  out.answer_clients();
  EXPECT_EQ(test::read_with_deadline(asker, {2s}, [](std::string_view b) { return b.find('>') != b.npos; }).bytes,
            "<ANSWER>");
  EXPECT_EQ(test::read_with_deadline(other, {300ms}, [](std::string_view) { return false; }).bytes, "")
      << "the answer went to a client that did not ask";
  ASSERT_EQ(::write(other, "poll", 4), 4);
  ASSERT_TRUE(service_until(out, [&] { return input.writers.size() == 2; }));
  EXPECT_NE(input.writers[1], input.writers[0]);
  ::close(asker);
  ASSERT_TRUE(service_until(out, [&] { return input.left.size() == 1; }));
  EXPECT_EQ(input.left[0], input.writers[0]);
  ::close(other);
}

TEST(TcpOutputTest, EachClientGetsWholeEpochsFromTheFirstAfterItConnects) {
  TcpOutput out("127.0.0.1", 0);
  ASSERT_NE(out.port(), 0);
  EXPECT_EQ(out.describe(), "tcp:127.0.0.1:" + std::to_string(out.port()));
  const int first = connect_client(out.port());
  ASSERT_TRUE(service_until(out, [&] { return out.client_count() == 1; }));
  std::string early;
  for (int k = 0; k < 5; ++k) {
    ASSERT_EQ(out.write_epoch(epoch(k)), WriteStatus::ok);
    early += epoch(k);
  }
  const int second = connect_client(out.port());
  ASSERT_TRUE(service_until(out, [&] { return out.client_count() == 2; }));
  std::string late;
  for (int k = 5; k < 10; ++k) {
    ASSERT_EQ(out.write_epoch(epoch(k)), WriteStatus::ok);
    late += epoch(k);
  }
  EXPECT_EQ(read_exactly(first, early.size() + late.size()), early + late);
  EXPECT_EQ(read_exactly(second, late.size()), late);
  EXPECT_EQ(out.tcp_stats().clients_accepted, 2u);
  ::close(first);
  ::close(second);
  ASSERT_TRUE(service_until(out, [&] { return out.client_count() == 0; })) << "closed clients not noticed";
  EXPECT_EQ(out.tcp_stats().clients_closed, 2u);
  EXPECT_EQ(out.write_epoch(epoch(10)), WriteStatus::ok);  // nobody connected is not a failure
}

TEST(TcpOutputTest, StalledClientIsDroppedWithoutDelayingTheOtherOrTheWriter) {
  TcpOutputOptions options;
  options.client_buffer_bytes = 8 * 1024;
  options.socket_send_buffer_bytes = 8 * 1024;
  TcpOutput out("127.0.0.1", 0, options);
  const int stalled = connect_client(out.port(), 4096);  // connected, never reads
  const int reader = connect_client(out.port());
  ASSERT_TRUE(service_until(out, [&] { return out.client_count() == 2; }));

  auto slowest_write = Clock::duration::zero();
  auto slowest_delivery = Clock::duration::zero();
  std::string received;
  int k = 0;
  for (; k < 3000 && out.tcp_stats().clients_dropped_slow == 0; ++k) {
    const std::string e = epoch(k);
    const auto start = Clock::now();
    ASSERT_EQ(out.write_epoch(e), WriteStatus::ok);
    slowest_write = std::max(slowest_write, Clock::now() - start);
    const std::string got = read_exactly(reader, e.size());
    slowest_delivery = std::max(slowest_delivery, Clock::now() - start);
    ASSERT_EQ(got, e) << "the reading client fell behind at epoch " << k;
    received += got;
    out.service();
  }
  ASSERT_EQ(out.tcp_stats().clients_dropped_slow, 1u) << "the stalled client was never dropped";
  EXPECT_EQ(out.client_count(), 1u);
  EXPECT_LT(slowest_write, 50ms);
  EXPECT_LT(slowest_delivery, 500ms);
  // The other client goes on after the drop.
  for (int j = 0; j < 5; ++j, ++k) {
    ASSERT_EQ(out.write_epoch(epoch(k)), WriteStatus::ok);
    EXPECT_EQ(read_exactly(reader, epoch(k).size()), epoch(k));
  }
  // What the stalled client had received before it was cut off is whole sentences up to the
  // last complete one (the connection ends; a reader sees end of file).
  const std::string stalled_got = test::read_available(stalled, 1000ms, 60s);
  const test::SplitResult split = test::split_sentences(stalled_got);
  EXPECT_EQ(split.invalid, 0u);
  EXPECT_GT(split.sentences.size(), 0u);
  std::printf("tcp fairness: stalled client dropped after %d epochs (%zu bytes reached it); slowest write %.3f ms, "
              "slowest delivery to the reading client %.3f ms\n",
              k, stalled_got.size(), std::chrono::duration<double, std::milli>(slowest_write).count(),
              std::chrono::duration<double, std::milli>(slowest_delivery).count());
  ::close(stalled);
  ::close(reader);
}

TEST(TcpOutputTest, ClientInputIsReadAndDiscarded) {
  TcpOutput out("127.0.0.1", 0);
  const int client = connect_client(out.port());
  ASSERT_TRUE(service_until(out, [&] { return out.client_count() == 1; }));
  const std::string probe(10000, '?');
  ASSERT_EQ(::send(client, probe.data(), probe.size(), 0), static_cast<ssize_t>(probe.size()));
  ASSERT_TRUE(service_until(out, [&] { return out.tcp_stats().input_bytes_discarded == probe.size(); }));
  ASSERT_EQ(out.write_epoch(epoch(0)), WriteStatus::ok);
  EXPECT_EQ(read_exactly(client, epoch(0).size()), epoch(0));
  ::close(client);
}

TEST(TcpOutputTest, EpochsWrittenWithNoClientAreCountedInTheSummary) {
  TcpOutput out("127.0.0.1", 0);
  for (int i = 0; i < 3; ++i) ASSERT_EQ(out.write_epoch(epoch(i)), WriteStatus::ok);
  const int client = connect_client(out.port());
  ASSERT_TRUE(service_until(out, [&] { return out.client_count() == 1; }));
  ASSERT_EQ(out.write_epoch(epoch(3)), WriteStatus::ok);
  EXPECT_EQ(read_exactly(client, epoch(3).size()), epoch(3));
  EXPECT_EQ(out.tcp_stats().epochs_to_nobody, 3u);
  EXPECT_NE(out.clients_summary().find("3 of the epochs written had no client to go to"), std::string::npos)
      << out.clients_summary();
  ::close(client);
}

TEST(TcpOutputTest, ClientsBeyondTheLimitAreRefused) {
  TcpOutputOptions options;
  options.max_clients = 1;
  TcpOutput out("127.0.0.1", 0, options);
  const int a = connect_client(out.port());
  const int b = connect_client(out.port());
  ASSERT_TRUE(service_until(out, [&] { return out.tcp_stats().clients_refused == 1; }));
  EXPECT_EQ(out.client_count(), 1u);
  ::close(a);
  ::close(b);
}

TEST(TcpOutputTest, PortInUseIsRefusedNamingIt) {
  TcpOutput first("127.0.0.1", 0);
  try {
    TcpOutput second("127.0.0.1", first.port());
    ADD_FAILURE() << "bound twice";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("tcp:127.0.0.1:" + std::to_string(first.port())), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("in use"), std::string::npos) << e.what();
  }
}

TEST(TcpOutputTest, SpecsParseAndOpen) {
  EXPECT_EQ(to_string(parse_output_spec("tcp:10110")), "tcp:10110");
  EXPECT_EQ(parse_output_spec("tcp:10110").host, "");
  EXPECT_EQ(parse_output_spec("tcp:0.0.0.0:10110").host, "0.0.0.0");
  EXPECT_EQ(parse_output_spec("tcp:[::1]:10110").host, "::1");
  EXPECT_EQ(to_string(parse_output_spec("tcp:[::1]:10110")), "tcp:[::1]:10110");
  for (const std::string bad : {"tcp", "tcp:", "tcp:70000", "tcp:host:", "tcp:x"}) {
    EXPECT_THROW((void)parse_output_spec(bad), std::invalid_argument) << bad;
  }
  const auto out = make_output(parse_output_spec("tcp:0"), {});
  EXPECT_EQ(out->describe().rfind("tcp:127.0.0.1:", 0), 0u) << out->describe();
  EXPECT_GE(out->poll_fd(), 0);
}

}  // namespace tcp_test
}  // namespace
}  // namespace gpsemu::transport
