// The control socket's line server (posix::UnixLineServer) on real Unix sockets: a path another
// server answers on, or a file that is not a socket, is refused and left as it was; a socket file
// nobody listens on (a killed run's) is replaced; at the end only the file it made is removed; a
// client beyond the limit, a silent one (a watcher excepted), one that does not read its answers
// and a line too long are each told or dropped and counted (issue 33 points 1 and 2).
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/scratch.hpp"
#include "transport/posix/unix_line_server.hpp"

namespace gpsemu::posix {
namespace {
namespace unix_line_server_test {

using namespace std::chrono_literals;

UnixLineServer::Settings settings(std::chrono::milliseconds idle_timeout = 0ms) {
  return {{"too many", "too long", "idle", "evicted"}, idle_timeout};
}

sockaddr_un address_of(const std::string& path) {
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::memcpy(a.sun_path, path.data(), path.size());
  return a;
}

/// A client connected to `path` (blocking).
UniqueFd connect_to(const std::string& path) {
  UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
  const sockaddr_un a = address_of(path);
  if (::connect(fd.get(), reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) throw std::runtime_error("connect failed");
  return fd;
}

/// A socket file nobody listens on: bound, then closed without removing it (a killed run's).
void leave_stale_socket(const std::string& path) {
  UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
  const sockaddr_un a = address_of(path);
  ASSERT_EQ(::bind(fd.get(), reinterpret_cast<const sockaddr*>(&a), sizeof a), 0);
}

/// Services `server` (answering every line with `answer`) until `done` or 5 s pass.
bool serve_until(UnixLineServer& server, const std::function<bool()>& done, const std::string& answer = "ok",
                 std::chrono::milliseconds give_up = 5000ms) {
  const auto deadline = std::chrono::steady_clock::now() + give_up;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::vector<int> fds;
    server.fds(fds);
    std::vector<pollfd> p;
    for (const int fd : fds) p.push_back({fd, POLLIN, 0});
    (void)::poll(p.data(), p.size(), 20);
    server.service([&answer](std::string_view) { return answer; });
  }
  return true;
}

/// The next line `fd` receives ("" when it closes or nothing comes within 5 s).
std::string read_line(int fd) {
  std::string line;
  char c = 0;
  pollfd p{fd, POLLIN, 0};
  while (::poll(&p, 1, 5000) > 0 && ::recv(fd, &c, 1, 0) == 1 && c != '\n') line += c;
  return line;
}

/// One request through unix_request (a client thread) while `server` is serviced.
std::string ask(UnixLineServer& server, const std::string& path, const std::string& line) {
  std::string answer;
  bool finished = false;
  std::thread client([&] {
    try {
      answer = unix_request(path, line, 5000ms);
    } catch (const std::exception& e) {
      answer = e.what();
    }
    finished = true;
  });
  const std::uint64_t before = server.stats().lines_answered;
  (void)serve_until(server, [&] { return server.stats().lines_answered > before; });
  client.join();
  EXPECT_TRUE(finished);
  return answer;
}

TEST(UnixLineServer, AStaleSocketIsReplacedALiveOneAndOtherFilesAreRefusedAndLeft) {
  const auto dir = test::scratch_dir("transport", "unix-line-taken");
  const std::string path = (dir / "ctl.sock").string();
  leave_stale_socket(path);
  UnixLineServer first(path, settings());
  EXPECT_EQ(ask(first, path, "status"), "ok");

  try {
    UnixLineServer second(path, settings());
    ADD_FAILURE() << "a second server took the live socket";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("control socket " + path + ": in use: another process answers on it"),
              std::string::npos)
        << e.what();
  }
  ASSERT_TRUE(std::filesystem::exists(path));
  EXPECT_EQ(ask(first, path, "still there?"), "ok");

  const std::string plain = (dir / "notes.txt").string();
  std::ofstream(plain) << "keep me\n";
  EXPECT_THROW(UnixLineServer(plain, settings()), std::runtime_error);
  std::ifstream kept(plain);
  std::string text;
  std::getline(kept, text);
  EXPECT_EQ(text, "keep me");
  std::filesystem::remove_all(dir);
}

TEST(UnixLineServer, AtTheEndOnlyTheFileItMadeIsRemoved) {
  const auto dir = test::scratch_dir("transport", "unix-line-own");
  const std::string path = (dir / "ctl.sock").string();
  {
    UnixLineServer server(path, settings());
    ASSERT_TRUE(std::filesystem::exists(path));
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  {
    UnixLineServer server(path, settings());
    // Someone removes it and puts their own socket there while the server runs.
    ASSERT_EQ(::unlink(path.c_str()), 0);
    leave_stale_socket(path);
  }
  EXPECT_TRUE(std::filesystem::exists(path)) << "the server removed a file it did not make";
  std::filesystem::remove_all(dir);
}

TEST(UnixLineServer, AClientBeyondTheLimitIsToldAndEachDropIsCounted) {
  const auto dir = test::scratch_dir("transport", "unix-line-drops");
  const std::string path = (dir / "ctl.sock").string();
  UnixLineServer server(path, settings());
  std::vector<UniqueFd> clients;
  for (std::size_t i = 0; i < UnixLineServer::kMaxClients; ++i) clients.push_back(connect_to(path));
  ASSERT_TRUE(serve_until(server, [&] { return server.stats().clients_accepted == UnixLineServer::kMaxClients; }));
  UniqueFd extra = connect_to(path);
  ASSERT_TRUE(serve_until(server, [&] { return server.stats().clients_refused == 1; }));
  EXPECT_EQ(read_line(extra.get()), "too many");

  // A line too long: told once, skipped to its end; the next line is answered.
  const std::string line = std::string(UnixLineServer::kMaxLineBytes + 100, 'x') + "\nnext\n";
  ASSERT_EQ(::send(clients[0].get(), line.data(), line.size(), MSG_NOSIGNAL), static_cast<ssize_t>(line.size()));
  ASSERT_TRUE(serve_until(server, [&] { return server.stats().lines_answered == 1; }));
  EXPECT_EQ(read_line(clients[0].get()), "too long");
  EXPECT_EQ(read_line(clients[0].get()), "ok");
  EXPECT_EQ(server.stats().lines_too_long, 1u);

  // A client that asks and never reads: dropped when its answers no longer fit, counted.
  const std::string big(64 * 1024, 'a');
  const std::string request = "status\n";
  int sent = 0;
  const bool dropped = serve_until(
      server,
      [&] {
        if (server.stats().clients_not_reading == 1) return true;
        if (::send(clients[1].get(), request.data(), request.size(), MSG_NOSIGNAL | MSG_DONTWAIT) > 0) ++sent;
        return false;
      },
      big);
  EXPECT_TRUE(dropped) << sent << " requests sent";
  EXPECT_EQ(server.stats().clients_not_reading, 1u);
  std::filesystem::remove_all(dir);
}

TEST(UnixLineServer, ASilentClientIsToldAndClosedAfterTheIdleTimeoutAWatcherStays) {
  const auto dir = test::scratch_dir("transport", "unix-line-idle");
  const std::string path = (dir / "ctl.sock").string();
  UnixLineServer server(path, settings(50ms));
  UniqueFd silent = connect_to(path);
  UniqueFd watcher = connect_to(path);
  const std::string watch = "watch\n";
  ASSERT_EQ(::send(watcher.get(), watch.data(), watch.size(), MSG_NOSIGNAL), static_cast<ssize_t>(watch.size()));
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (server.stats().clients_idle_closed == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(20ms);
    server.service([](std::string_view, std::optional<std::int64_t>& w) {
      w = -1;
      return std::string("watching");
    });
  }
  EXPECT_EQ(server.stats().clients_idle_closed, 1u);
  EXPECT_EQ(read_line(silent.get()), "idle");
  char c = 0;
  EXPECT_EQ(::recv(silent.get(), &c, 1, 0), 0);  // closed
  EXPECT_EQ(read_line(watcher.get()), "watching");
  EXPECT_EQ(server.watchers(), 1u);
  server.push("epoch", 0);
  EXPECT_EQ(read_line(watcher.get()), "epoch");
  std::filesystem::remove_all(dir);
}

// `printf '{"status":true}' | nc -U PATH`: the last line has no '\n' and the client shuts its end
// to wait for the answer. It was dropped unanswered and uncounted; it is answered like any line.
TEST(UnixLineServer, ALastLineWithoutItsEndIsAnsweredWhenTheClientShutsItsEnd) {
  const auto dir = test::scratch_dir("transport", "unix-line-eof");
  const std::string path = (dir / "ctl.sock").string();
  UnixLineServer server(path, settings());
  UniqueFd client = connect_to(path);
  const std::string request = "first\nlast";
  ASSERT_EQ(::send(client.get(), request.data(), request.size(), MSG_NOSIGNAL), static_cast<ssize_t>(request.size()));
  ASSERT_EQ(::shutdown(client.get(), SHUT_WR), 0);
  ASSERT_TRUE(serve_until(server, [&] { return server.stats().lines_answered == 2; }, "answer"));
  EXPECT_EQ(read_line(client.get()), "answer");
  EXPECT_EQ(read_line(client.get()), "answer");
  char c = 0;
  EXPECT_EQ(::recv(client.get(), &c, 1, 0), 0);  // then closed
  std::filesystem::remove_all(dir);
}

}  // namespace unix_line_server_test
}  // namespace
}  // namespace gpsemu::posix
