// The bench view's HTTP server (--ui [HOST:]PORT): the page and its assets (embedded in the
// binary), the hub's epochs as Server-Sent Events, and fault requests that go through the hub to
// the loop. cpp-httplib (Debian's libcpp-httplib-dev) does the HTTP on its own worker threads;
// nothing here runs on the loop's thread. Limits, each refusal counted (stats(), the exit summary):
// requests over 64 KiB, more than kMaxStreams event streams, state-changing requests that are not
// a POST of application/json (a cross-site form or <img> cannot send one), that name a Host or
// Origin other than the server's on a loopback bind, or that lack the token on any other bind;
// a chunked body read past 64 KiB, JSON nested too deep or with a key twice (before it is parsed);
// a connection whose request (line, headers, body) has not arrived whole within a few seconds
// (slowloris: request_deadline.hpp), or an event stream that does not read its events, is closed.
// The headers (type, token, origin) are checked before a byte of a body is read.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "emulator/ui/hub.hpp"
#include "emulator/ui/request_deadline.hpp"
#include "emulator/ui/ui_spec.hpp"

namespace httplib {
class Server;
}

namespace gpsemu::ui {

class HttpServer {
 public:
  static constexpr int kWorkers = 16;      ///< threads serving connections, at first
  static constexpr int kMaxWorkers = 64;   ///< and at most, while connections wait for one
  static constexpr int kMaxStreams = 8;    ///< event streams at once (pages open)
  static constexpr std::size_t kMaxBodyBytes = 64 * 1024;  ///< a request body, whatever its framing
  static constexpr int kRequestTimeoutS = 3;  ///< a request's line and headers whole within (seconds)
  static constexpr int kBodyTimeoutS = 3;     ///< and then its body

  struct Stats {
    std::uint64_t connections = 0;
    std::uint64_t connections_without_request = 0;  ///< closed idle or malformed before a whole request
    std::uint64_t requests = 0;
    std::uint64_t malformed = 0;         ///< answered 400 (bad request line, headers, URI too long)
    std::uint64_t too_large = 0;         ///< answered 413
    std::uint64_t refused_token = 0;     ///< answered 403: no token or a wrong one
    std::uint64_t refused_cross_site = 0;  ///< answered 403/415: not a JSON POST, or another Host/Origin
    std::uint64_t streams_refused = 0;   ///< answered 503: kMaxStreams open
    std::uint64_t streams_dropped = 0;   ///< event streams closed because they did not read
    std::uint64_t control_requests = 0;  ///< fault requests passed to the loop
    std::uint64_t closed_slow = 0;       ///< closed: a request not whole within kRequestTimeoutS (or its body kBodyTimeoutS)
    std::uint64_t refused_shape = 0;     ///< answered 422: JSON nested too deep or a key twice (faults/json_shape.hpp)
  };

  /// Binds at once (throws std::runtime_error naming the address when it cannot), before anything
  /// else opens (a port in use must not cost the outputs' files); serves nothing until serve().
  explicit HttpServer(HttpSettings settings);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  /// "http://127.0.0.1:8080/" (with "#token=..." when a token is needed).
  /// Serves `hub`'s epochs and requests from its own threads until destroyed.
  void serve(Hub& hub);
  [[nodiscard]] std::string url() const;
  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] bool token_required() const { return token_.has_value(); }
  [[nodiscard]] Stats stats() const;
  /// The exit summary's line.
  [[nodiscard]] std::string summary() const;

 private:
  class CountingPool;
  struct Counters;
  void routes();

  Hub* hub_ = nullptr;  ///< from serve() on
  HttpSettings settings_;
  std::optional<std::string> token_;
  std::uint16_t port_ = 0;
  int listening_fd_ = -1;  ///< httplib's listening socket (its backlog is raised after the bind)
  std::unique_ptr<Counters> counters_;
  std::unique_ptr<httplib::Server> server_;
  std::unique_ptr<RequestDeadline> deadline_;  ///< from the bind on
  std::thread thread_;
};

}  // namespace gpsemu::ui
