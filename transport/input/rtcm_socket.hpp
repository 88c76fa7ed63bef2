// RTCM3 input sockets (--rtcm tcp:[HOST:]PORT | udp:[HOST:]PORT): a base station's correction
// stream (str2str, an NTRIP client, a second emulator) as raw bytes. TCP: a server with a few
// client slots (posix::TcpServer), each connection its own byte stream; UDP: datagrams, one
// stream. Non-blocking, a bounded amount of work per call; what the bytes mean is the caller's
// business (rtk::Rtcm3Reader).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "emulator/config/spec/rtcm_input_spec.hpp"
#include "transport/posix/sockets.hpp"

namespace gpsemu::transport {

/// Bytes that arrived: `source` names the stream (UDP: the sender's address, TCP: the connection's
/// number), so the caller assembles frames per stream: bytes of two senders never mix.
struct RtcmBytes {
  std::string_view bytes;  ///< valid until the next receive()
  std::uint64_t source = 0;
  bool closed = false;     ///< TCP: the connection `source` ended (no bytes)
};

class RtcmSocket {
 public:
  virtual ~RtcmSocket() = default;
  RtcmSocket() = default;
  RtcmSocket(const RtcmSocket&) = delete;
  RtcmSocket& operator=(const RtcmSocket&) = delete;
  /// The next bytes or event, or nothing when nothing is ready. Never blocks.
  [[nodiscard]] virtual std::optional<RtcmBytes> receive() = 0;
  /// "tcp:127.0.0.1:2101", with the port actually bound.
  [[nodiscard]] virtual std::string describe() const = 0;
  /// The caller found a whole RTCM3 frame with a good CRC in `source`'s bytes: a base station.
  /// TCP: a connection that gave one keeps its slot against newcomers (one that never did, or is
  /// quiet kQuietS, gives it up); UDP: the first sender that gave one is the base, other senders'
  /// datagrams are dropped (counted) until it is quiet kQuietS.
  virtual void frame_from(std::uint64_t source) = 0;
  static constexpr int kQuietS = 2;
  struct Drops {
    std::uint64_t refused = 0;   ///< TCP: connections closed at once, every slot held by a base
    std::uint64_t replaced = 0;  ///< TCP: connections closed to make room (no frame, or quiet)
    std::uint64_t other_senders = 0;  ///< UDP: datagrams of a sender that is not the base
  };
  [[nodiscard]] virtual Drops drops() const = 0;
};

/// Listens (TCP) or binds (UDP). Throws std::runtime_error naming host:port when it cannot.
[[nodiscard]] std::unique_ptr<RtcmSocket> open_rtcm_socket(const RtcmInputSpec& spec);

}  // namespace gpsemu::transport
