// NMEA over TCP (`tcp:[HOST:]PORT`), as networked receivers and gpsd's own NMEA feeds serve it: a
// server (default bind 127.0.0.1) that any number of clients connect to, each receiving whole
// epochs from the first epoch after it connects. Each client has a bounded buffer; a client too
// slow to keep up (buffer full) is disconnected and counted, so it never delays the others or the
// epoch loop. Each connection is a client of its own (a ClientId): what it writes goes to the
// receiver's client input as its own stream (its own frame reader), the answer goes to it alone,
// behind the whole epochs queued for it (an answer that does not fit its buffer is dropped whole
// and counted), and its half-written input is forgotten when it disconnects. Listening socket and
// clients sit behind ONE pollable descriptor (posix::TcpServer).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "transport/output.hpp"
#include "transport/posix/tcp_server.hpp"

namespace gpsemu::transport {

struct TcpOutputOptions {
  /// More take the place of the client most behind (connected 2 s at least), else are closed at once (counted).
  std::size_t max_clients = 32;
  /// Bytes an epoch may wait for one client beyond what its socket buffer holds; a client whose
  /// backlog would pass this is disconnected (bytes).
  std::size_t client_buffer_bytes = 64 * 1024;
  /// The kernel send buffer of each client socket (SO_SNDBUF, bytes; 0: the system's default).
  /// Small keeps a slow client's data fresh and lets it be noticed within seconds.
  int socket_send_buffer_bytes = 32 * 1024;
};

struct TcpStats {
  std::uint64_t clients_accepted = 0;
  std::uint64_t clients_refused = 0;       ///< beyond max_clients, none connected kTakeOverAfter
  std::uint64_t clients_replaced = 0;      ///< closed for a newcomer: every slot taken, the one most behind
  std::uint64_t clients_dropped_slow = 0;  ///< disconnected because their buffer was full
  std::uint64_t clients_closed = 0;        ///< closed by the client (or reset)
  std::uint64_t input_bytes_discarded = 0;
  std::uint64_t epochs_to_nobody = 0;      ///< epochs written while no client was connected (sent to no one)
};

class TcpOutput final : public Output {
 public:
  /// Listens on `host`:`port` (an IP address or a name; port 0 picks a free one). Throws
  /// std::runtime_error naming host:port when it cannot (in use, unknown host, not local).
  TcpOutput(const std::string& host, std::uint16_t port, TcpOutputOptions options = {});

  /// Accepts clients, reads and discards their input, sends what waits for slow clients,
  /// notices closed connections. Bounded work per call.
  void service() override;
  [[nodiscard]] int poll_fd() const override { return server_.poll_fd(); }
  /// "tcp:127.0.0.1:10110".
  [[nodiscard]] std::string describe() const override { return description_; }

  [[nodiscard]] std::string clients_summary() const override;
  [[nodiscard]] std::uint16_t port() const { return server_.port(); }
  [[nodiscard]] std::size_t client_count() const { return server_.client_count(); }
  [[nodiscard]] std::optional<std::uint64_t> clients_connected() const override { return client_count(); }
  [[nodiscard]] const TcpStats& tcp_stats() const { return tcp_stats_; }

 protected:
  /// Sends the epoch to every client: ok when there is none too (nothing is waiting for it).
  WriteStatus write_bytes(std::string_view bytes, std::string& error_text) override;
  /// Queues an answer for the one client that asked (dropped when it has gone or has no room).
  WriteStatus write_reply(ClientId client, std::string_view bytes, std::string& error_text) override;

 private:
  /// A newcomer with every slot taken takes the place of a client connected this long at least.
  static constexpr std::chrono::milliseconds kTakeOverAfter{2000};
  [[nodiscard]] std::optional<std::size_t> most_behind() const;
  void handle(const posix::TcpServerEvent& event);
  void close_client(std::size_t slot, const char* why);
  /// Sends what waits; false when the connection failed (the caller closes it).
  bool send_pending(std::size_t slot);
  void report_drops();

  TcpOutputOptions options_;
  posix::TcpServer server_;
  std::string description_;
  /// Per client slot: bytes its socket did not take yet (whole epochs, the first partly sent).
  std::vector<std::string> pending_;
  std::vector<ClientId> ids_;  ///< per client slot: the connection's ClientId
  std::vector<std::chrono::steady_clock::time_point> connected_at_;  ///< per client slot
  std::vector<std::size_t> failed_, slow_;  ///< write_bytes' scratch lists (slots)
  TcpStats tcp_stats_;
  TcpStats reported_;
  LogLimit drop_log_{1};     ///< "disconnected ... too slow" lines: at most one a second
  LogLimit refused_log_{1};  ///< "refused client" lines: at most one a second
  LogLimit connect_log_{5};  ///< "client ... connected" lines: at most 5 a second
};

}  // namespace gpsemu::transport
