// libFuzzer target for the bench view's HTTP surface (--ui, emulator/ui/http_server.hpp) as an
// attacker on the same machine reaches it: the input is the bytes of one TCP connection to a real
// server on loopback (cpp-httplib's request parsing, then our routes: the assets, /api/info,
// /api/server, /api/events, /api/control through the hub to a loop thread producing epochs). The
// connection is half-closed after the input (the client sent all it will), its answer read for at
// most 256 KiB or a second, then closed.
// Checks: nothing crashes; every answer begins with an HTTP/1.1 status line; after each input a
// well-formed GET /api/info on a new connection is answered 200 with the receiver's JSON (the
// server neither locked up nor lost its workers); the server's counters only grow.
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <arpa/inet.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <thread>

#include "emulator/pipeline/channel_set.hpp"
#include "emulator/ui/http_server.hpp"
#include "emulator/ui/hub.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using namespace std::chrono_literals;
using gpsemu::UtcNs;

/// One receiver standing two metres east of its origin.
class StillSource final : public gpsemu::sources::PoseSource {
 public:
  std::optional<gpsemu::sources::Truth> truth_at(UtcNs) override {
    gpsemu::sources::Truth t{};
    t.position_m = {2.0, 0.0, 0.0};
    return t;
  }
  [[nodiscard]] std::string describe() const override { return "still"; }
};

/// The server, its hub and a loop thread that produces an epoch and answers the hub's requests
/// every millisecond, as gpsemu's loop does at its own rate.
struct Bench {
  gpsemu::Timeline timeline;
  gpsemu::ChannelSet set;
  std::unique_ptr<gpsemu::ui::Hub> hub;
  std::unique_ptr<gpsemu::ui::HttpServer> server;
  std::atomic<bool> stop{false};
  std::thread loop;

  static UtcNs t0() { return gpsemu::parse_iso8601_utc("2024-05-01T12:00:00Z"); }

  Bench()
      : timeline{gpsemu::EpochGrid(10.0), gpsemu::EpochGrid(10.0).index_at_or_after(t0()), 0ns},
        set{timeline, std::nullopt} {
    gpsemu::ChannelSettings s;
    s.origin = {43.0725, -89.4125, 260.0};
    auto ch = std::make_unique<gpsemu::Channel>(s, t0());
    ch->set_source(std::make_unique<StillSource>());
    set.add(std::move(ch));
    hub = std::make_unique<gpsemu::ui::Hub>(set, 0ns);
    set.set_observer(hub.get());
    server = std::make_unique<gpsemu::ui::HttpServer>(gpsemu::ui::HttpSettings{"127.0.0.1", 0, std::nullopt});
    server->serve(*hub);
    loop = std::thread([this] {
      UtcNs t{};
      while (!stop.load()) {
        if (set.next_epoch(t)) (void)set.produce(0, t);
        hub->service();
        std::this_thread::sleep_for(1ms);
      }
    });
  }
};

Bench& bench() {
  static Bench* b = new Bench();  // lives to the process's end: libFuzzer exits without unwinding
  return *b;
}

int connect_to(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  GPSEMU_FUZZ_CHECK(fd >= 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  GPSEMU_FUZZ_CHECK(::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0);
  return fd;
}

/// Reads into `answer` until `fd` closes, is quiet for `quiet`, 256 KiB came or a second passed
/// (an event stream does not end). Whether the server closed the connection.
bool read_answer(int fd, std::string& answer, std::chrono::milliseconds quiet) {
  const auto until = std::chrono::steady_clock::now() + 1s;
  char buf[16384];
  while (answer.size() < 256 * 1024 && std::chrono::steady_clock::now() < until) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(quiet.count())) <= 0) return false;
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) return true;
    answer.append(buf, static_cast<std::size_t>(n));
  }
  return false;
}

/// Writes what it can of `bytes` (the server may close early: a 400, a 413) and reads what comes
/// until it is quiet; then half-closes (the client sent all it will: a request left incomplete
/// ends now, not at the server's read timeout) and reads the rest. Not half-closed at once:
/// cpp-httplib 0.11 drops a connection whose end of input is already there when a worker first
/// reads it, unanswered (measured: a GET with SHUT_WR straight after it gets nothing; 50 ms
/// later it is answered), which no browser or HTTP library does.
std::string exchange(std::uint16_t port, std::string_view bytes) {
  const int fd = connect_to(port);
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) break;
    sent += static_cast<std::size_t>(n);
  }
  std::string answer;
  if (!read_answer(fd, answer, 30ms)) {
    ::shutdown(fd, SHUT_WR);
    (void)read_answer(fd, answer, 2000ms);
  }
  ::close(fd);
  return answer;
}

bool status_line(std::string_view answer) {
  return answer.size() >= 13 && answer.substr(0, 9) == "HTTP/1.1 " && answer[9] >= '1' && answer[9] <= '5' &&
         answer[10] >= '0' && answer[10] <= '9' && answer[11] >= '0' && answer[11] <= '9' && answer[12] == ' ';
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bench& b = bench();
  const std::uint16_t port = b.server->port();
  const gpsemu::ui::HttpServer::Stats before = b.server->stats();

  const std::string answer = exchange(port, {reinterpret_cast<const char*>(data), size});
  GPSEMU_FUZZ_CHECK(answer.empty() || status_line(answer));

  // A page arriving after it is served as ever (the workers' deadline is a few seconds: allow it).
  const std::string info = exchange(port, "GET /api/info HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
  GPSEMU_FUZZ_CHECK(info.rfind("HTTP/1.1 200 ", 0) == 0);
  GPSEMU_FUZZ_CHECK(info.find("\"receivers\":1") != std::string::npos);

  const gpsemu::ui::HttpServer::Stats after = b.server->stats();
  GPSEMU_FUZZ_CHECK(after.connections >= before.connections + 1);
  GPSEMU_FUZZ_CHECK(after.requests >= before.requests + 1);
  GPSEMU_FUZZ_CHECK(after.malformed >= before.malformed && after.too_large >= before.too_large &&
                    after.refused_shape >= before.refused_shape && after.control_requests >= before.control_requests);
  return 0;
}
