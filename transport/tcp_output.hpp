// NMEA over TCP (`tcp:[HOST:]PORT`), as networked receivers and gpsd's own NMEA feeds serve it: a
// server (default bind 127.0.0.1) that any number of clients connect to, each receiving whole
// epochs from the first epoch after it connects. Each client has a bounded buffer; a client too
// slow to keep up (buffer full) is disconnected and counted, so it never delays the others or the
// epoch loop. Client input is read and discarded. Listening socket and clients sit behind ONE
// pollable descriptor (an internal epoll instance).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "transport/output.hpp"

namespace gpsemu::transport {

struct TcpOutputOptions {
  std::size_t max_clients = 32;  ///< more are accepted and closed at once (counted)
  /// Bytes an epoch may wait for one client beyond what its socket buffer holds; a client whose
  /// backlog would pass this is disconnected (bytes).
  std::size_t client_buffer_bytes = 64 * 1024;
  /// The kernel send buffer of each client socket (SO_SNDBUF, bytes; 0: the system's default).
  /// Small keeps a slow client's data fresh and lets it be noticed within seconds.
  int socket_send_buffer_bytes = 32 * 1024;
};

struct TcpStats {
  std::uint64_t clients_accepted = 0;
  std::uint64_t clients_refused = 0;       ///< beyond max_clients
  std::uint64_t clients_dropped_slow = 0;  ///< disconnected because their buffer was full
  std::uint64_t clients_closed = 0;        ///< closed by the client (or reset)
  std::uint64_t input_bytes_discarded = 0;
};

class TcpOutput final : public Output {
 public:
  /// Listens on `host`:`port` (an IP address or a name; port 0 picks a free one). Throws
  /// std::runtime_error naming host:port when it cannot (in use, unknown host, not local).
  TcpOutput(const std::string& host, std::uint16_t port, TcpOutputOptions options = {});
  ~TcpOutput() override;

  /// Accepts clients, reads and discards their input, sends what waits for slow clients,
  /// notices closed connections. Bounded work per call.
  void service() override;
  [[nodiscard]] int poll_fd() const override { return epoll_fd_; }
  /// "tcp:127.0.0.1:10110".
  [[nodiscard]] std::string describe() const override { return description_; }

  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] std::size_t client_count() const { return clients_.size(); }
  [[nodiscard]] const TcpStats& tcp_stats() const { return tcp_stats_; }

 protected:
  /// Sends the epoch to every client: ok when there is none too (nothing is waiting for it).
  WriteStatus write_bytes(std::string_view bytes, std::string& error_text) override;

 private:
  struct Client {
    int fd = -1;
    std::string name;     ///< "127.0.0.1:50123"
    std::string pending;  ///< bytes its socket did not take yet (whole epochs, the first partly sent)
    bool want_out = false;
  };
  void accept_clients();
  void close_client(std::uint64_t id, const char* why);
  /// Sends what waits; false when the connection failed (the caller closes it).
  bool send_pending(std::uint64_t id, Client& client);
  void update_interest(std::uint64_t id, Client& client);
  void report_drops();

  TcpOutputOptions options_;
  int listen_fd_ = -1;
  int epoll_fd_ = -1;
  std::uint16_t port_ = 0;
  std::string description_;
  std::uint64_t next_id_ = 1;  ///< epoll data of a client; 0 is the listening socket
  std::map<std::uint64_t, Client> clients_;
  TcpStats tcp_stats_;
  TcpStats reported_;
  std::chrono::steady_clock::time_point last_report_{};
};

}  // namespace gpsemu::transport
