// One TCP server for every TCP endpoint of the emulator (the NMEA output's clients, the pose
// input's simulators): a listening socket and its clients behind ONE pollable descriptor (an epoll
// instance), a fixed number of client slots, connections beyond them accepted and closed at once
// (or, when the caller names one, a client is closed to make room for the newcomer), and events handed out one at a time so the caller bounds its work by bounding its calls. What
// is read from or written to a client is the caller's business (per slot, in its own arrays).
#pragma once

#include <sys/epoll.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "transport/posix/fd.hpp"

namespace gpsemu::posix {

struct TcpServerOptions {
  std::size_t max_clients = 8;     ///< slots; more connections are accepted and closed at once
  bool no_delay = false;           ///< TCP_NODELAY on each client: small writes leave at once
  int send_buffer_bytes = 0;       ///< SO_SNDBUF of each client (bytes); 0: the system's default
  /// Every slot taken and a client connects: the slot whose client is closed to make room for it,
  /// or nothing to refuse the newcomer. Empty: newcomers are refused.
  std::function<std::optional<std::size_t>()> take_over{};
};

/// One thing that happened on the server.
struct TcpServerEvent {
  enum class Kind {
    connected,  ///< a client took `slot`
    refused,    ///< a client beyond max_clients was closed at once (no slot)
    ready,      ///< the client in `slot` is readable (data, end of file or error) or writable
  };
  Kind kind = Kind::ready;
  std::size_t slot = 0;
  std::uint64_t serial = 0;   ///< the connection's number, from 1 in accept order
  std::string_view peer;      ///< "127.0.0.1:50123"; valid until the slot is taken again
  bool readable = false;      ///< ready: data, end of file, hang-up or an error waits for a read
  bool writable = false;      ///< ready: the socket takes more bytes (when asked for, see watch)
  std::uint64_t replaced = 0; ///< connected: serial of the client closed to make room (0: none)
};

class TcpServer {
 public:
  /// Listens on host:port (port 0 picks a free one). Throws std::runtime_error beginning with
  /// `context` ("tcp output: cannot listen on tcp:127.0.0.1:10110") when it cannot.
  TcpServer(const std::string& host, std::uint16_t port, const std::string& context, TcpServerOptions options);

  /// The next event, or nothing when nothing is ready. Never blocks; at most one epoll_wait and
  /// one accept per call.
  [[nodiscard]] std::optional<TcpServerEvent> next_event();

  /// Closes the client in `slot` and frees the slot.
  void drop(std::size_t slot);
  /// What to wait for on the client in `slot`: its input, its room for output (both false: nothing).
  void watch(std::size_t slot, bool read, bool write);

  [[nodiscard]] int client_fd(std::size_t slot) const { return clients_[slot].fd.get(); }
  [[nodiscard]] bool occupied(std::size_t slot) const { return clients_[slot].serial != 0; }
  /// "127.0.0.1:50123": the client in `slot`, or the last one refused or dropped from it.
  [[nodiscard]] std::string_view peer(std::size_t slot) const {
    return std::string_view(clients_[slot].peer.data(), clients_[slot].peer_len);
  }
  [[nodiscard]] std::size_t slots() const { return clients_.size(); }
  [[nodiscard]] std::size_t client_count() const { return client_count_; }

  /// Readable when next_event() may have something.
  [[nodiscard]] int poll_fd() const { return epoll_.get(); }
  [[nodiscard]] std::uint16_t port() const { return port_; }
  /// The bound address: "127.0.0.1:10110", "[::1]:10110".
  [[nodiscard]] const std::string& address() const { return address_; }

 private:
  struct Client {
    UniqueFd fd;
    std::uint64_t serial = 0;  ///< 0: free slot
    std::array<char, 64> peer{};
    std::size_t peer_len = 0;
    bool read = false, write = false;
  };
  [[nodiscard]] std::optional<TcpServerEvent> accept_one();

  TcpServerOptions options_;
  UniqueFd listen_, epoll_;
  std::uint16_t port_ = 0;
  std::string address_;
  std::vector<Client> clients_;
  Client refused_;  ///< holds a refused client's name for its event
  std::size_t client_count_ = 0;
  std::uint64_t serial_counter_ = 0;
  std::array<epoll_event, 16> events_{};
  int event_count_ = 0, next_event_ = 0;
};

}  // namespace gpsemu::posix
