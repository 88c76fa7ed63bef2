// NMEA over UDP (`udp:HOST:PORT`): one datagram an epoch, all its sentences, to a unicast,
// broadcast or multicast address. Nothing waits for a listener: a datagram the kernel cannot take
// at once is dropped whole and counted; nobody listening is not an error.
#pragma once

#include <cstdint>
#include <string>

#include "transport/output.hpp"
#include "transport/posix/fd.hpp"

namespace gpsemu::transport {

class UdpOutput final : public Output {
 public:
  /// Resolves `host` (an address or a name) and opens a non-blocking socket (broadcast allowed).
  /// Throws std::runtime_error naming host:port when the host cannot be resolved.
  UdpOutput(const std::string& host, std::uint16_t port);

  /// "udp:127.0.0.1:10110".
  [[nodiscard]] std::string describe() const override { return description_; }
  /// "; N datagrams reported unreachable (...)" when the destination said nobody was listening.
  [[nodiscard]] std::string clients_summary() const override;
  /// Datagrams the destination reported unreachable (ICMP port unreachable, seen as ECONNREFUSED
  /// on the next send): written, but nobody was listening.
  [[nodiscard]] std::uint64_t unreachable() const { return unreachable_; }

 protected:
  WriteStatus write_bytes(std::string_view bytes, std::string& error_text) override;

 private:
  std::string description_;
  posix::UniqueFd fd_;
  std::uint64_t unreachable_ = 0;
};

}  // namespace gpsemu::transport
