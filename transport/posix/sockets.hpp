// Sockets: parsing and resolving HOST:PORT and opening a socket on the first address that works (one
// getaddrinfo loop for every listener, receiver and sender), the texts that name addresses in
// messages, and receiving a datagram with its kernel time stamp and the kernel's drop count.
#pragma once

#include <netdb.h>
#include <sys/socket.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>
#include <string_view>

#include "emulator/config/spec/endpoint.hpp"
#include "transport/posix/fd.hpp"
#include "transport/posix/wall_clock.hpp"

namespace gpsemu::posix {


/// "203.0.113.5:50123" or "[::1]:50123" written into `out` without allocating; returns the length
/// written (cut to fit). "?" for a family that is neither IPv4 nor IPv6.
std::size_t format_address(const sockaddr_storage& address, std::span<char> out);
/// format_address as a string.
[[nodiscard]] std::string address_text(const sockaddr_storage& address);
/// The local port a socket is bound to (0 when it is not an IP socket).
[[nodiscard]] std::uint16_t bound_port(int fd);
/// A server's listening socket (the bench view's, set up by cpp-httplib): SO_REUSEADDR (and not
/// SO_REUSEPORT: a second server on the same port is refused), and a send buffer of
/// `send_buffer_bytes` that its connections inherit, so a client that stops reading fills it in
/// seconds, not minutes. Errors are ignored (the defaults stay).
void configure_listening_socket(int fd, int send_buffer_bytes);
/// Sets a listening socket's backlog again (Linux takes a second listen() as a new backlog): a
/// library that listens with a few slots (cpp-httplib: 5) makes every connect beyond them wait
/// for a SYN retransmission, a second.
void set_listen_backlog(int fd, int backlog);
/// A TCP connection this process accepted, and its peer as address_text() writes it.
struct AcceptedConnection {
  int fd = -1;
  std::string peer;
};
/// The connected TCP sockets of this process whose local port is `port` (a server's connections,
/// served by another library's threads), found by looking at each open descriptor (/proc/self/fd).
[[nodiscard]] std::vector<AcceptedConnection> connections_on_port(std::uint16_t port);
/// Ends a connection another thread serves, if `fd` is still connected to `peer`: shutdown() both
/// ways, so that thread's next read ends and it closes the descriptor itself (never reused under it).
bool shut_down_connection(int fd, std::string_view peer);

/// The bytes a connected TCP socket holds that it could not send yet (TCP_INFO's notsent: the
/// peer's window is full), or nothing when the kernel does not say.
[[nodiscard]] std::optional<std::uint32_t> tcp_unsent_bytes(int fd);

/// Raises this process's limit of open descriptors to its hard limit (many clients at once);
/// returns the soft limit in force.
std::uint64_t raise_open_files_limit();

/// What open_socket() resolves and opens.
struct SocketRequest {
  std::string host{};       ///< a name or address; empty: every interface (passive) or the loopback
  std::uint16_t port = 0;   ///< 0 with passive: the system picks a free port
  int type = SOCK_STREAM;   ///< SOCK_STREAM or SOCK_DGRAM
  bool passive = true;      ///< addresses to bind (AI_PASSIVE), else addresses to connect to
  bool blocking = false;    ///< else the socket is opened non-blocking
  /// How error messages begin, naming host:port ("cannot listen on tcp:127.0.0.1:5005"). They read
  /// "<context>: host '<host>': <resolver's reason>" or "<context>: <failure><why the last address failed>".
  std::string context{};
  std::string_view failure{};  ///< e.g. "cannot open a socket: "; empty by default
};

/// Called on each candidate socket (close-on-exec, non-blocking unless asked otherwise): set
/// options, bind or connect. Returns 0 when the socket is ready, else the errno (the next address
/// is tried).
using SocketSetup = std::function<int(int fd, const addrinfo& address)>;

/// Resolves request.host:port and returns the socket of the first address `setup` accepts.
/// Throws std::runtime_error worded as SocketRequest::context says (EADDRINUSE reads "the port is
/// in use by another program").
[[nodiscard]] UniqueFd open_socket(const SocketRequest& request, const SocketSetup& setup);

/// A listening TCP socket (SO_REUSEADDR: a restart binds while old connections linger).
[[nodiscard]] UniqueFd listen_tcp(const SocketRequest& request, int backlog = 16);
/// A bound socket of request.type; `configure` sets options before bind (may be empty).
[[nodiscard]] UniqueFd bind_socket(const SocketRequest& request, const std::function<void(int fd)>& configure = {});
/// A connected socket of request.type (request.passive is ignored); `configure` sets options before
/// connect (may be empty). A UDP socket's connect only fixes the destination.
[[nodiscard]] UniqueFd connect_socket(const SocketRequest& request, const std::function<void(int fd)>& configure = {});

/// Asks the kernel to stamp each datagram's arrival (SO_TIMESTAMPNS, CLOCK_REALTIME) and to count
/// the datagrams it drops (SO_RXQ_OVFL). Returns 0 or the errno of SO_TIMESTAMPNS.
int enable_datagram_stamps(int fd);

/// One datagram received by receive_datagram().
struct Datagram {
  std::size_t size = 0;               ///< its whole length (may exceed the buffer: then it was cut)
  std::optional<WallTime> kernel_time;  ///< when the kernel received it (SO_TIMESTAMPNS), if stamped
  std::optional<std::uint32_t> drop_counter;  ///< the socket's running count of dropped datagrams (SO_RXQ_OVFL)
  sockaddr_storage from{};
};

/// Receives one datagram into `buffer` without blocking; nothing when none waits (or on an error
/// the next call sees again).
[[nodiscard]] std::optional<Datagram> receive_datagram(int fd, std::span<char> buffer);

/// Turns the kernel's running drop counter (a 32-bit count that wraps) into drops since the last call.
class DropCounter {
 public:
  /// Datagrams dropped since the counter was last seen.
  std::uint32_t update(std::uint32_t counter) {
    const std::uint32_t dropped = counter - seen_;
    seen_ = counter;
    return dropped;
  }

 private:
  std::uint32_t seen_ = 0;
};

}  // namespace gpsemu::posix
