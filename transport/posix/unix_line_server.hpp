// A Unix-domain (or loopback TCP) stream socket that takes text lines from a few clients and
// answers each line with one line (the control socket: JSON lines in, one JSON answer each). Never blocks: the caller
// polls fds() and calls service() when one is readable. A line longer than kMaxLineBytes, or a
// client whose answers do not fit its socket buffer, is dropped (counted); a client beyond
// kMaxClients is told so and closed. The socket file is removed when the server goes.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "transport/posix/fd.hpp"

namespace gpsemu::posix {

class UnixLineServer {
 public:
  static constexpr std::size_t kMaxClients = 8;
  static constexpr std::size_t kMaxLineBytes = 4096;
  /// Answers one line (without its '\n'); the answer is sent followed by '\n'.
  using Handler = std::function<std::string(std::string_view line)>;
  /// What the server tells a client it refuses, or a line too long (one line each).
  struct Messages {
    std::string too_many_clients;
    std::string line_too_long;
  };

  /// Listens on `path` (a stale socket file there is replaced; any other file is an error).
  /// Throws std::runtime_error beginning with "control socket PATH: ".
  UnixLineServer(std::string path, Messages messages);
  /// The same on a listening socket made by the caller (listen_tcp()); `name` ("tcp:127.0.0.1:5005")
  /// stands for it in path() and messages, and no file is removed.
  UnixLineServer(UniqueFd listening, std::string name, Messages messages);
  ~UnixLineServer();
  UnixLineServer(const UnixLineServer&) = delete;
  UnixLineServer& operator=(const UnixLineServer&) = delete;

  /// The descriptors to poll for input (the listening socket and each client).
  void fds(std::vector<int>& out) const;
  /// Accepts new clients, reads what waits and answers every complete line with `handle`.
  void service(const Handler& handle);

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] std::uint64_t lines_answered() const { return lines_answered_; }
  [[nodiscard]] std::uint64_t clients_dropped() const { return clients_dropped_; }

 private:
  struct Client {
    UniqueFd fd;
    std::string pending;  ///< a line not yet ended
    bool discarding = false;  ///< inside a line too long: skip to its end
  };
  /// Sends `text` + '\n' whole, or returns false (the client is then dropped).
  static bool send_line(int fd, std::string_view text);

  std::string path_;
  Messages messages_;
  UniqueFd listen_;
  bool owns_file_ = true;  ///< a Unix socket's file, removed at the end
  std::vector<Client> clients_;
  std::uint64_t lines_answered_ = 0;
  std::uint64_t clients_dropped_ = 0;
};

/// A client's one exchange: connects to the server at `path`, sends `line` + '\n' and returns the
/// first line of the answer (without '\n'). Throws std::runtime_error ("control socket PATH: ...")
/// when it cannot connect or no answer comes within `timeout`.
[[nodiscard]] std::string unix_request(const std::string& path, std::string_view line, std::chrono::milliseconds timeout);
/// The same over TCP to `host`:`port` ("control socket tcp:HOST:PORT: ...").
[[nodiscard]] std::string tcp_request(const std::string& host, std::uint16_t port, std::string_view line,
                                      std::chrono::milliseconds timeout);

}  // namespace gpsemu::posix
