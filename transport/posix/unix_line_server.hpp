// A Unix-domain (or loopback TCP) stream socket that takes text lines from a few clients and
// answers each line with one line (the control socket: JSON lines in, one JSON answer each). Never blocks: the caller
// polls fds() and calls service() when one is readable (and between epochs). A client's last line
// may lack its '\n' (it is answered when the client shuts its end). A line longer than
// kMaxLineBytes, or a client whose answers do not fit its socket buffer, is dropped; a client beyond
// kMaxClients takes the slot of one that sent no request for kEvictAfter, or is told so and closed;
// a client silent for the idle timeout is told so and closed (empty lines are not requests: they
// keep nobody in), so idle connections never lock the operator out; each counted in stats(). A
// client is answered kLinesPerService lines a call and kLinesPerSecond a second, so one that
// pipelines requests never holds the loop (the rest later; its sends block meanwhile). A path where another
// server answers is refused; the socket file is removed when the server goes, if it is still ours.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "transport/posix/fd.hpp"

namespace gpsemu::posix {

class UnixLineServer {
 public:
  static constexpr std::size_t kMaxClients = 8;
  static constexpr std::size_t kMaxLineBytes = 4096;
  /// Lines answered a client a call of service() at most, and the bytes read from it at a time.
  static constexpr std::size_t kLinesPerService = 4;
  static constexpr std::size_t kReadBytes = 4096;
  /// A client's lines answered a second at most, on average, and in a burst.
  static constexpr std::size_t kLinesPerSecond = 100;
  static constexpr std::size_t kLinesBurst = 32;
  /// When every slot is taken, a newcomer takes the slot of the client whose last request is
  /// oldest, if that is at least this long ago (a watcher keeps its slot).
  static constexpr std::chrono::milliseconds kEvictAfter{std::chrono::seconds(2)};
  /// Answers one line (without its '\n'); the answer is sent followed by '\n'.
  using Handler = std::function<std::string(std::string_view line)>;
  /// The same; setting `watch` makes the client a watcher of push()'s lines (its value: the one
  /// tag it wants, or -1 for all). A watcher is never closed idle.
  using WatchHandler = std::function<std::string(std::string_view line, std::optional<std::int64_t>& watch)>;
  static constexpr std::chrono::milliseconds kDefaultIdleTimeout{std::chrono::seconds(30)};
  /// What the server tells a client it refuses, a line too long, or an idle client it closes (one line each).
  struct Messages {
    std::string too_many_clients;
    std::string line_too_long;
    std::string idle_closed;
    std::string evicted;  ///< closed for a newcomer: no request for kEvictAfter, every slot taken
  };
  struct Settings {
    Messages messages;
    /// A client that sent no complete line for this long is closed (zero: never).
    std::chrono::milliseconds idle_timeout = kDefaultIdleTimeout;
  };
  /// What happened to the clients and their lines since the start.
  struct Stats {
    std::uint64_t lines_answered = 0;
    std::uint64_t clients_accepted = 0;
    std::uint64_t clients_refused = 0;      ///< beyond kMaxClients: told so and closed
    std::uint64_t clients_idle_closed = 0;  ///< silent for the idle timeout: told so and closed
    std::uint64_t clients_not_reading = 0;  ///< an answer did not fit their socket: dropped
    std::uint64_t lines_too_long = 0;       ///< over kMaxLineBytes: answered with an error, skipped
    std::uint64_t lines_pushed = 0;         ///< push()'s lines sent to watchers
    std::uint64_t clients_evicted = 0;      ///< closed for a newcomer (make_room)
    std::uint64_t empty_lines = 0;          ///< skipped: neither a request nor activity
    std::uint64_t clients_throttled = 0;    ///< times a client's requests were held to kLinesPerSecond
  };

  /// Listens on `path`: a socket file nobody listens on (left by a run that died) is replaced;
  /// a socket another process answers on, or any other file, is refused. Throws
  /// std::runtime_error beginning with "control socket PATH: ".
  UnixLineServer(std::string path, Settings settings);
  /// The same on a listening socket made by the caller (listen_tcp()); `name` ("tcp:127.0.0.1:5005")
  /// stands for it in path() and messages, and no file is removed.
  UnixLineServer(UniqueFd listening, std::string name, Settings settings);
  ~UnixLineServer();
  UnixLineServer(const UnixLineServer&) = delete;
  UnixLineServer& operator=(const UnixLineServer&) = delete;

  /// The descriptors to poll for input (the listening socket and each client).
  void fds(std::vector<int>& out) const;
  /// Accepts new clients, reads what waits and answers every complete line with `handle`.
  void service(const Handler& handle);
  void service(const WatchHandler& handle);
  /// Sends `line` to every watcher of `tag` (or of all); one whose socket is full is dropped
  /// (counted in clients_not_reading). Never blocks.
  void push(std::string_view line, std::int64_t tag);
  /// Watchers connected now.
  [[nodiscard]] std::size_t watchers() const;

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] const Stats& stats() const { return stats_; }
  [[nodiscard]] std::chrono::milliseconds idle_timeout() const { return settings_.idle_timeout; }

 private:
  struct Client {
    UniqueFd fd;
    std::chrono::steady_clock::time_point last_line;  ///< connected, or its last complete line
    std::string pending;  ///< a line not yet ended
    bool discarding = false;  ///< inside a line too long: skip to its end
    std::optional<std::int64_t> watch{};  ///< a watcher of push()'s lines with this tag (-1: all)
    bool closed_by_peer = false;  ///< its end closed with lines left to answer
    double credit = static_cast<double>(kLinesBurst);  ///< lines it may send now (kLinesPerSecond refill it)
    std::chrono::steady_clock::time_point credit_at{};
    bool throttled = false;  ///< its last call ended on its rate
  };
  /// With every slot taken: closes the client quiet longest, if quiet kEvictAfter; false if none is.
  bool make_room(std::chrono::steady_clock::time_point now);
  /// Answers c's complete lines in `pending`, `budget` at most (it counts down); false: drop c.
  bool answer_pending(Client& c, const WatchHandler& handle, std::size_t& budget, std::chrono::steady_clock::time_point now);
  /// Closes the clients silent for longer than the idle timeout.
  void close_idle(std::chrono::steady_clock::time_point now);
  /// Sends `text` + '\n' whole, or returns false (the client is then dropped).
  static bool send_line(int fd, std::string_view text);

  std::string path_;
  Settings settings_;
  UniqueFd listen_;
  bool owns_file_ = true;  ///< a Unix socket's file, removed at the end if it is still the one we made
  std::uint64_t file_device_ = 0, file_inode_ = 0;  ///< that file's identity
  std::vector<Client> clients_;
  Stats stats_;
  /// Readable when a client has more lines than one call answered (timerfd): the loop comes back
  /// at once, or when a throttled client's rate allows another line.
  UniqueFd wake_;
};

/// A client's one exchange: connects to the server at `path`, sends `line` + '\n' and returns the
/// first line of the answer (without '\n'). Throws std::runtime_error ("control socket PATH: ...")
/// when it cannot connect or no answer comes within `timeout`.
[[nodiscard]] std::string unix_request(const std::string& path, std::string_view line, std::chrono::milliseconds timeout);
/// The same over TCP to `host`:`port` ("control socket tcp:HOST:PORT: ...").
[[nodiscard]] std::string tcp_request(const std::string& host, std::uint16_t port, std::string_view line,
                                      std::chrono::milliseconds timeout);
/// Takes each line of an answer; false: no more.
using LineSink = std::function<bool(std::string_view line)>;
/// A client's exchange that goes on (a watcher): sends `line`, gives `sink` every line that comes
/// back until it returns false or the server closes; throws like unix_request, or when no line
/// comes for `timeout`.
void unix_exchange(const std::string& path, std::string_view line, std::chrono::milliseconds timeout, const LineSink& sink);
void tcp_exchange(const std::string& host, std::uint16_t port, std::string_view line, std::chrono::milliseconds timeout,
                  const LineSink& sink);

}  // namespace gpsemu::posix
