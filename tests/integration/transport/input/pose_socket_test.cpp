// Pose sockets on loopback: endpoint parsing, UDP datagrams (with their sender and kernel arrival
// time, oversized ones refused), the TCP line server (lines split across reads, CR LF, overlong
// and partial lines, the client limit) and bind errors that name host:port. Waits with poll().
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include "transport/input/pose_socket.hpp"

namespace gpsemu::transport {
namespace {
namespace pose_socket_test {

using namespace std::chrono;
using Kind = ReceivedMessage::Kind;

struct Event {
  Kind kind;
  std::string bytes;
  std::string sender_name;
  sys_time<nanoseconds> arrival;
};

/// Receives until `count` events arrived or `timeout` passed, waiting on poll_fd().
std::vector<Event> receive_events(PoseSocket& s, std::size_t count, milliseconds timeout = milliseconds(3000)) {
  std::vector<Event> out;
  const auto deadline = steady_clock::now() + timeout;
  while (out.size() < count && steady_clock::now() < deadline) {
    while (auto m = s.receive()) {
      out.push_back({m->kind, std::string(m->bytes), std::string(m->sender_name), m->arrival});
      if (out.size() == count) return out;
    }
    pollfd p{s.poll_fd(), POLLIN, 0};
    poll(&p, 1, 50);
  }
  return out;
}

sockaddr_in loopback(std::uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return a;
}

int udp_sender() { return socket(AF_INET, SOCK_DGRAM, 0); }

void send_udp(int fd, std::uint16_t port, const std::string& bytes) {
  const auto a = loopback(port);
  ASSERT_EQ(sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&a), sizeof a),
            static_cast<ssize_t>(bytes.size()));
}

int tcp_connect(std::uint16_t port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  const auto a = loopback(port);
  if (connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

void send_all(int fd, const std::string& bytes) {
  ASSERT_EQ(write(fd, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
}

TEST(PoseEndpoint, ParsesPortHostAndBracketedIpv6) {
  auto e = parse_pose_endpoint("5005");
  EXPECT_EQ(e.host, "127.0.0.1");
  EXPECT_EQ(e.port, 5005);
  e = parse_pose_endpoint("0.0.0.0:6000");
  EXPECT_EQ(e.host, "0.0.0.0");
  EXPECT_EQ(e.port, 6000);
  e = parse_pose_endpoint("[::1]:7000");
  EXPECT_EQ(e.host, "::1");
  EXPECT_EQ(e.port, 7000);
  e = parse_pose_endpoint("localhost:0");
  EXPECT_EQ(e.port, 0);
}

TEST(PoseEndpoint, RefusesBadPortsAndUnbracketedIpv6) {
  for (const char* bad : {"", "abc", "70000", "-1", "5005x", "host:", ":5005", "::1:5005", "[::1]5005", "[::1"}) {
    EXPECT_THROW((void)parse_pose_endpoint(bad), std::invalid_argument) << bad;
  }
}

TEST(UdpPoseSocket, ReturnsEachDatagramWithItsSenderAndKernelArrivalTime) {
  auto s = open_udp_pose_socket({"127.0.0.1", 0});
  ASSERT_GT(s->port(), 0);
  EXPECT_EQ(s->describe(), "udp:127.0.0.1:" + std::to_string(s->port()));
  EXPECT_FALSE(s->receive());
  const int tx = udp_sender();
  const auto before = time_point_cast<nanoseconds>(system_clock::now());
  send_udp(tx, s->port(), R"({"x":1,"y":2})");
  send_udp(tx, s->port(), "second");
  const auto after = time_point_cast<nanoseconds>(system_clock::now());
  const auto events = receive_events(*s, 2);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, Kind::message);
  EXPECT_EQ(events[0].bytes, R"({"x":1,"y":2})");
  EXPECT_EQ(events[1].bytes, "second");
  EXPECT_EQ(events[0].sender_name.rfind("127.0.0.1:", 0), 0u) << events[0].sender_name;
  EXPECT_GE(events[0].arrival, before - milliseconds(1));
  EXPECT_LE(events[0].arrival, after + milliseconds(1));
  close(tx);
}

TEST(UdpPoseSocket, DatagramsOverTheLimitAreReportedNotReturned) {
  auto s = open_udp_pose_socket({"127.0.0.1", 0}, {.max_message_bytes = 4096});
  const int tx = udp_sender();
  int size = 65000;  // near the largest UDP datagram
  setsockopt(tx, SOL_SOCKET, SO_SNDBUF, &size, sizeof size);
  send_udp(tx, s->port(), std::string(65000, 'x'));
  send_udp(tx, s->port(), std::string(4097, 'y'));
  send_udp(tx, s->port(), std::string(4096, 'z'));
  const auto events = receive_events(*s, 3);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].kind, Kind::too_large);
  EXPECT_TRUE(events[0].bytes.empty());
  EXPECT_EQ(events[1].kind, Kind::too_large);
  EXPECT_EQ(events[2].kind, Kind::message);
  EXPECT_EQ(events[2].bytes.size(), 4096u);
  close(tx);
}

TEST(UdpPoseSocket, BindErrorsNameHostAndPort) {
  auto first = open_udp_pose_socket({"127.0.0.1", 0});
  const std::string where = "127.0.0.1:" + std::to_string(first->port());
  try {
    (void)open_udp_pose_socket({"127.0.0.1", first->port()});
    FAIL() << "bound a port in use";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
  }
  try {
    (void)open_udp_pose_socket({"no-such-host.invalid", 5005});
    FAIL() << "bound an unknown host";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-host.invalid:5005"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)open_udp_pose_socket({"192.0.2.1", 5005}), std::runtime_error);  // not this machine's
}

TEST(TcpPoseServer, SplitsLinesAcrossReadsAndReportsConnectAndPartialLineAtClose) {
  auto s = open_tcp_pose_server({"127.0.0.1", 0});
  EXPECT_EQ(s->describe(), "tcp:127.0.0.1:" + std::to_string(s->port()));
  const int c = tcp_connect(s->port());
  ASSERT_GE(c, 0);
  auto events = receive_events(*s, 1);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::connected);
  EXPECT_NE(events[0].sender_name.find("(tcp #"), std::string::npos) << events[0].sender_name;

  send_all(c, "{\"a\":");
  EXPECT_TRUE(receive_events(*s, 1, milliseconds(100)).empty());  // half a line: nothing yet
  send_all(c, "1}\nsecond\r\n\n\nthird-without-newline");
  events = receive_events(*s, 2);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].bytes, "{\"a\":1}");
  EXPECT_EQ(events[1].bytes, "second");  // CR stripped, blank lines skipped
  close(c);
  events = receive_events(*s, 2);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, Kind::partial_line);
  EXPECT_EQ(events[1].kind, Kind::disconnected);
}

TEST(TcpPoseServer, AnOverlongLineIsReportedOnceAndTheNextLineStillArrives) {
  auto s = open_tcp_pose_server({"127.0.0.1", 0}, {.max_message_bytes = 100, .max_clients = 8});
  const int c = tcp_connect(s->port());
  ASSERT_GE(c, 0);
  send_all(c, std::string(5000, 'x') + "\n" + "ok\n" + std::string(101, 'y') + "\nok2\n");
  const auto events = receive_events(*s, 5);
  ASSERT_EQ(events.size(), 5u);
  EXPECT_EQ(events[0].kind, Kind::connected);
  EXPECT_EQ(events[1].kind, Kind::too_large);
  EXPECT_EQ(events[2].bytes, "ok");
  EXPECT_EQ(events[3].kind, Kind::too_large);
  EXPECT_EQ(events[4].bytes, "ok2");
  close(c);
}

TEST(TcpPoseServer, ALineOfExactlyTheLimitIsAccepted) {
  auto s = open_tcp_pose_server({"127.0.0.1", 0}, {.max_message_bytes = 100, .max_clients = 8});
  const int c = tcp_connect(s->port());
  send_all(c, std::string(100, 'a') + "\r\n" + std::string(100, 'b') + "\n");
  const auto events = receive_events(*s, 3);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[1].bytes, std::string(100, 'a'));
  EXPECT_EQ(events[2].bytes, std::string(100, 'b'));
  close(c);
}

TEST(TcpPoseServer, SeveralClientsUpToTheLimitAndTheRestAreRefused) {
  auto s = open_tcp_pose_server({"127.0.0.1", 0}, {.max_message_bytes = 100, .max_clients = 2});
  const int a = tcp_connect(s->port()), b = tcp_connect(s->port()), c = tcp_connect(s->port());
  auto events = receive_events(*s, 3);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].kind, Kind::connected);
  EXPECT_EQ(events[1].kind, Kind::connected);
  EXPECT_EQ(events[2].kind, Kind::refused_client);
  char byte;
  pollfd p{c, POLLIN, 0};
  ASSERT_EQ(poll(&p, 1, 3000), 1);
  EXPECT_EQ(read(c, &byte, 1), 0) << "the refused client is closed";
  send_all(a, "from-a\n");
  send_all(b, "from-b\n");
  events = receive_events(*s, 2);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_NE(events[0].sender_name, events[1].sender_name);
  // A freed slot takes a new client.
  close(a);
  events = receive_events(*s, 1);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::disconnected);
  const int d = tcp_connect(s->port());
  events = receive_events(*s, 1);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::connected);
  close(b);
  close(c);
  close(d);
}

TEST(TcpPoseServer, PortInUseNamesHostAndPort) {
  auto first = open_tcp_pose_server({"127.0.0.1", 0});
  try {
    (void)open_tcp_pose_server({"127.0.0.1", first->port()});
    FAIL() << "listened on a port in use";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("tcp:127.0.0.1:" + std::to_string(first->port())), std::string::npos)
        << e.what();
  }
}

}  // namespace pose_socket_test
}  // namespace
}  // namespace gpsemu::transport
