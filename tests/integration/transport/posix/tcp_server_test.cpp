// The one TCP server (posix::TcpServer) on real loopback sockets: clients take slots and are named
// by address, one beyond the limit is accepted and closed at once, a dropped client frees its slot
// for the next (whose events are never confused with the old one's), readiness to read and write
// comes through the one pollable descriptor, and a port in use is refused naming host:port.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>

#include "transport/posix/sockets.hpp"
#include "transport/posix/tcp_server.hpp"

namespace gpsemu::posix {
namespace {
namespace tcp_server_test {

using namespace std::chrono_literals;
using Kind = TcpServerEvent::Kind;

UniqueFd connect_client(std::uint16_t port) {
  return connect_socket({.host = "127.0.0.1", .port = port, .blocking = true, .context = "test client"});
}

/// Waits on the server's one descriptor for its next event (up to `timeout`).
std::optional<TcpServerEvent> next(TcpServer& server, std::chrono::milliseconds timeout = 3s) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (auto e = server.next_event()) return e;
    pollfd pfd{server.poll_fd(), POLLIN, 0};
    (void)::poll(&pfd, 1, 20);
  }
  return std::nullopt;
}

TEST(TcpServer, NamesItsAddressAndEachClient) {
  TcpServer server("127.0.0.1", 0, "test", {.max_clients = 2});
  ASSERT_NE(server.port(), 0);
  EXPECT_EQ(server.address(), "127.0.0.1:" + std::to_string(server.port()));
  const UniqueFd client = connect_client(server.port());
  const auto e = next(server);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind, Kind::connected);
  EXPECT_EQ(e->slot, 0u);
  EXPECT_EQ(e->serial, 1u);
  EXPECT_EQ(std::string(e->peer), "127.0.0.1:" + std::to_string(bound_port(client.get())));
  EXPECT_EQ(server.client_count(), 1u);
  EXPECT_TRUE(server.occupied(0));
  EXPECT_FALSE(server.occupied(1));
}

TEST(TcpServer, ReportsInputAndEndOfFileAsReadable) {
  TcpServer server("127.0.0.1", 0, "test", {.max_clients = 1});
  UniqueFd client = connect_client(server.port());
  ASSERT_EQ(next(server)->kind, Kind::connected);
  ASSERT_EQ(::send(client.get(), "hello\n", 6, 0), 6);
  auto e = next(server);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind, Kind::ready);
  EXPECT_TRUE(e->readable);
  char buf[16];
  EXPECT_EQ(::read(server.client_fd(e->slot), buf, sizeof buf), 6);
  client.reset();
  e = next(server);
  ASSERT_TRUE(e);
  EXPECT_TRUE(e->readable);
  const Drained d = drain_input(server.client_fd(e->slot), 1024);
  EXPECT_EQ(d.end, Drained::End::closed);
  server.drop(e->slot);
  EXPECT_EQ(server.client_count(), 0u);
}

TEST(TcpServer, AClientBeyondTheLimitIsClosedAtOnce) {
  TcpServer server("127.0.0.1", 0, "test", {.max_clients = 1});
  const UniqueFd first = connect_client(server.port());
  ASSERT_EQ(next(server)->kind, Kind::connected);
  const UniqueFd second = connect_client(server.port());
  const auto e = next(server);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind, Kind::refused);
  EXPECT_EQ(e->serial, 2u);
  EXPECT_EQ(std::string(e->peer), "127.0.0.1:" + std::to_string(bound_port(second.get())));
  EXPECT_EQ(server.client_count(), 1u);
  pollfd pfd{second.get(), POLLIN, 0};
  ASSERT_EQ(::poll(&pfd, 1, 3000), 1);
  char c;
  EXPECT_LE(::recv(second.get(), &c, 1, 0), 0);  // end of file (or reset): the server closed it
}

TEST(TcpServer, ADroppedClientsQueuedEventIsIgnoredAndItsSlotGoesToTheNext) {
  TcpServer server("127.0.0.1", 0, "test", {.max_clients = 2});
  const UniqueFd a = connect_client(server.port());
  const UniqueFd b = connect_client(server.port());
  ASSERT_EQ(next(server)->kind, Kind::connected);
  ASSERT_EQ(next(server)->kind, Kind::connected);
  ASSERT_EQ(::send(a.get(), "x", 1, 0), 1);
  ASSERT_EQ(::send(b.get(), "y", 1, 0), 1);
  ::usleep(50'000);  // both bytes arrived: one epoll_wait reports both clients
  const auto first = next(server);
  ASSERT_TRUE(first);
  ASSERT_EQ(first->kind, Kind::ready);
  char c;
  ASSERT_EQ(::read(server.client_fd(first->slot), &c, 1), 1);
  const std::size_t other = 1 - first->slot;
  server.drop(other);  // its event is still queued in the server
  EXPECT_FALSE(server.next_event());  // ... and is not reported
  const UniqueFd d = connect_client(server.port());
  const auto e = next(server);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind, Kind::connected);
  EXPECT_EQ(e->slot, other);
  EXPECT_EQ(e->serial, 3u);
  EXPECT_EQ(server.client_count(), 2u);
}

TEST(TcpServer, WritableOnlyWhenAskedFor) {
  TcpServer server("127.0.0.1", 0, "test", {.max_clients = 1, .no_delay = true, .send_buffer_bytes = 8192});
  const UniqueFd client = connect_client(server.port());
  const auto c = next(server);
  ASSERT_EQ(c->kind, Kind::connected);
  EXPECT_FALSE(next(server, 100ms));  // connected and idle: nothing to report
  server.watch(c->slot, true, true);
  const auto e = next(server);
  ASSERT_TRUE(e);
  EXPECT_TRUE(e->writable);
  EXPECT_FALSE(e->readable);
  server.watch(c->slot, true, false);
  EXPECT_FALSE(next(server, 100ms));
}

TEST(TcpServer, APortInUseIsRefusedNamingHostAndPort) {
  TcpServer first("127.0.0.1", 0, "test", {});
  const std::string where = "tcp:" + host_port("127.0.0.1", first.port());
  try {
    TcpServer second("127.0.0.1", first.port(), "cannot listen on " + where, {});
    FAIL() << "listened twice";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "cannot listen on " + where + ": the port is in use by another program");
  }
}

}  // namespace tcp_server_test
}  // namespace
}  // namespace gpsemu::posix
