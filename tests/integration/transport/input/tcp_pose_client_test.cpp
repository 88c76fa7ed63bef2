// The TCP client of a byte stream (pose_socket.hpp: open_tcp_pose_client, what mavlink:tcp uses)
// against a real listening socket on loopback: it connects, returns the bytes as they were read,
// reports the peer's close, reconnects after the retry interval, and connects to a server that
// starts after it. Waits with poll().
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/support/tcp_listener.hpp"
#include "transport/input/pose_socket.hpp"

namespace gpsemu::transport {
namespace {
namespace tcp_pose_client_test {

using namespace std::chrono;
using Kind = ReceivedMessage::Kind;
using test::Listener;

struct Event {
  Kind kind;
  std::string bytes;
  std::uint64_t sender;
};

/// Receives until an event of `until` arrived or `timeout` passed; every event on the way.
std::vector<Event> receive_until(PoseSocket& s, Kind until, milliseconds timeout = milliseconds(5000)) {
  std::vector<Event> out;
  const auto deadline = steady_clock::now() + timeout;
  while (steady_clock::now() < deadline) {
    while (auto m = s.receive()) {
      out.push_back({m->kind, std::string(m->bytes), m->sender});
      if (m->kind == until) return out;
    }
    pollfd p{s.poll_fd(), POLLIN, 0};
    poll(&p, s.poll_fd() < 0 ? 0 : 1, 20);  // waiting to retry: no descriptor, a short sleep
  }
  return out;
}

std::string bytes_of(const std::vector<Event>& events) {
  std::string all;
  for (const Event& e : events) {
    if (e.kind == Kind::message) all += e.bytes;
  }
  return all;
}

void send_all(int fd, const std::string& bytes) { ASSERT_EQ(::send(fd, bytes.data(), bytes.size(), 0), static_cast<ssize_t>(bytes.size())); }

TEST(TcpPoseClient, ConnectsReadsBytesAndReconnectsAfterThePeerCloses) {
  const Listener server;
  auto client = open_tcp_pose_client({"127.0.0.1", server.port()}, {.max_message_bytes = 4096}, milliseconds(100));
  EXPECT_EQ(client->describe(), "tcp:127.0.0.1:" + std::to_string(server.port()));
  const auto connected = receive_until(*client, Kind::connected);
  ASSERT_FALSE(connected.empty());
  const int first = server.accept_one();
  ASSERT_GE(first, 0);
  EXPECT_EQ(connected.back().kind, Kind::connected);
  const std::uint64_t first_sender = connected.back().sender;

  send_all(first, std::string("\xfd\x01\x02", 3));
  send_all(first, "frame bytes, no lines\n\n");
  ::close(first);
  const auto read = receive_until(*client, Kind::disconnected);
  ASSERT_FALSE(read.empty());
  EXPECT_EQ(read.back().kind, Kind::disconnected);
  EXPECT_EQ(bytes_of(read), std::string("\xfd\x01\x02", 3) + "frame bytes, no lines\n\n");

  // The client tries again after 100 ms, from receive(); the kernel completes the connection
  // before the server accepts it.
  const auto again = receive_until(*client, Kind::connected);
  ASSERT_FALSE(again.empty());
  const int second = server.accept_one();
  ASSERT_GE(second, 0);
  EXPECT_NE(again.back().sender, first_sender);  // another connection: another sender
  send_all(second, "more");
  EXPECT_EQ(bytes_of(receive_until(*client, Kind::message)), "more");
  ::close(second);
}

TEST(TcpPoseClient, ConnectsToAServerThatStartsLater) {
  std::uint16_t port = 0;
  {
    const Listener probe;  // a port that was free a moment ago
    port = probe.port();
  }
  auto client = open_tcp_pose_client({"127.0.0.1", port}, {}, milliseconds(100));
  EXPECT_TRUE(receive_until(*client, Kind::connected, milliseconds(300)).empty());  // refused, retrying
  const Listener server(port);
  const auto events = receive_until(*client, Kind::connected);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().kind, Kind::connected);
  const int fd = server.accept_one();
  ASSERT_GE(fd, 0);
  ::close(fd);
}

TEST(TcpPoseClient, AnUnknownHostIsAnErrorNamingIt) {
  try {
    (void)open_tcp_pose_client({"no-such-host.invalid", 5760});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot connect to tcp:no-such-host.invalid:5760: host 'no-such-host.invalid'"),
              std::string::npos) << e.what();
  }
}

}  // namespace tcp_pose_client_test
}  // namespace
}  // namespace gpsemu::transport
