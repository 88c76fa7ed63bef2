// Pose sockets: where an external simulator's pose messages come in. A UDP receiver (one message
// per datagram) and a TCP line server (one message per '\n'-terminated line, several clients),
// both non-blocking behind ONE pollable file descriptor (the TCP server is posix::TcpServer, as
// the NMEA tcp output's). A TCP client that sends no complete line for the idle timeout is closed,
// and when every slot is taken a newcomer takes the slot of the client idle longest (idle for at
// least the take-over time); docs/pose-input.md. A TCP client of a byte stream (MAVLink) too. They return raw messages with their arrival time and sender; decoding is
// the caller's business.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "transport/posix/sockets.hpp"

namespace gpsemu::transport {

/// Where to listen: "[HOST:]PORT"; HOST defaults to 127.0.0.1, an IPv6 literal goes in brackets
/// ("[::1]:5005"); PORT 0 picks a free port (describe() then names it).
using PoseEndpoint = posix::Endpoint;

/// Parses "[HOST:]PORT" (posix::parse_endpoint). Throws std::invalid_argument naming the text.
[[nodiscard]] inline PoseEndpoint parse_pose_endpoint(std::string_view text) { return posix::parse_endpoint(text); }

struct PoseSocketOptions {
  std::size_t max_message_bytes = 4096;  ///< longer datagrams or lines are refused (reported, not returned)
  std::size_t max_clients = 8;           ///< TCP: connections beyond this are accepted and closed at once
  /// TCP: a client without a complete line ('\n'-terminated, blank ones too) for this long is closed.
  std::chrono::nanoseconds idle_timeout{std::chrono::seconds(5)};
  /// TCP: every slot taken, a newcomer closes the client idle longest if idle at least this long
  /// (otherwise the newcomer is refused): clients that send are never pushed out.
  std::chrono::nanoseconds take_over_idle{std::chrono::seconds(1)};
};

/// One thing that happened on a pose socket.
struct ReceivedMessage {
  enum class Kind {
    message,            ///< `bytes` holds one datagram or one line (without '\n')
    too_large,          ///< a datagram or line longer than max_message_bytes was discarded
    partial_line,       ///< a TCP client closed the connection in the middle of a line
    kernel_dropped,     ///< UDP: the kernel dropped `count` datagrams (receive buffer full)
    connected,          ///< TCP: a client connected
    disconnected,       ///< TCP: a client closed (or reset) its connection
    refused_client,     ///< TCP: a client beyond max_clients was closed at once
    idle_closed,        ///< TCP: a client sent no complete line for the idle timeout and was closed
    taken_over,         ///< TCP: an idle client was closed to make room for a new connection
  };
  Kind kind = Kind::message;
  std::string_view bytes;          ///< message only; valid until the next receive()
  std::chrono::sys_time<std::chrono::nanoseconds> arrival{};  ///< CLOCK_REALTIME (UDP: kernel time stamp)
  std::uint64_t sender = 0;        ///< identifies the sender: UDP source address and port, or TCP connection
  std::string_view sender_name;    ///< "127.0.0.1:50123" (UDP) or "127.0.0.1:50123 (tcp #3)"; valid until next receive()
  std::uint64_t count = 1;         ///< kernel_dropped: datagrams dropped since the last report
};

class PoseSocket {
 public:
  virtual ~PoseSocket() = default;
  PoseSocket() = default;
  PoseSocket(const PoseSocket&) = delete;
  PoseSocket& operator=(const PoseSocket&) = delete;

  /// The next event, or nothing when nothing is ready. Never blocks; does a bounded amount of
  /// work (a few system calls) per call, so callers bound their work by bounding the calls.
  [[nodiscard]] virtual std::optional<ReceivedMessage> receive() = 0;
  /// Readable when receive() may have something.
  [[nodiscard]] virtual int poll_fd() const = 0;
  /// "udp:127.0.0.1:5005", with the port actually bound.
  [[nodiscard]] virtual std::string describe() const = 0;
  [[nodiscard]] virtual std::uint16_t port() const = 0;
  /// Writes `bytes` back to `sender` (a TCP client socket: to the peer it connected to), without
  /// blocking. False when this socket cannot answer or not all the bytes went out.
  [[nodiscard]] virtual bool reply(std::uint64_t /*sender*/, std::span<const std::uint8_t> /*bytes*/) { return false; }
};

/// Binds a UDP receiver. Throws std::runtime_error naming host:port when it cannot (port in use,
/// unknown host, address not on this machine).
[[nodiscard]] std::unique_ptr<PoseSocket> open_udp_pose_socket(const PoseEndpoint& endpoint,
                                                               const PoseSocketOptions& options = {});
/// Listens for TCP clients. Throws std::runtime_error naming host:port when it cannot.
[[nodiscard]] std::unique_ptr<PoseSocket> open_tcp_pose_server(const PoseEndpoint& endpoint,
                                                               const PoseSocketOptions& options = {});

/// A TCP client of a byte stream (tcp_pose_client.cpp: a MAVLink port such as ArduPilot SITL's
/// 5760): connects to `endpoint` without blocking, returns what each read() brought as one
/// `message` (at most options.max_message_bytes; not lines), `connected` and `disconnected` events,
/// and reconnects `retry` after a failed attempt or a dropped connection (failures are logged,
/// once per streak). Throws std::runtime_error naming host:port when the host does not resolve.
[[nodiscard]] std::unique_ptr<PoseSocket> open_tcp_pose_client(const PoseEndpoint& endpoint,
                                                               const PoseSocketOptions& options = {},
                                                               std::chrono::nanoseconds retry = std::chrono::seconds(1));

}  // namespace gpsemu::transport
