// Protocol encoders (ArduPilot SITL's shape: one fix, many encoders). The receiver model fills one
// plain fix structure an epoch (nmea::Fix: protocol-neutral fields, pure); each encoder of a
// channel publishes it into the epoch's bytes, in the order they were added. A protocol that also
// reads what the client writes (UBX polls and configuration) takes those bytes through
// client_wrote(); its answers (ACKs) leave at once through take_reply(), which the output that
// read the bytes writes back right after servicing them (Output::answer_clients()).
#pragma once

#include <string>
#include <string_view>

#include "nmea/fix.hpp"
#include "nmea/sentences.hpp"
#include "transport/output.hpp"

namespace gpsemu {

class Encoder {
 public:
  virtual ~Encoder() = default;
  /// Appends this protocol's bytes for `fix` to `out` (which holds the earlier encoders' bytes).
  virtual void encode(const nmea::Fix& fix, std::string& out) = 0;
  /// Bytes `client` wrote to one of the receiver's outputs, in arrival order. Default: ignored.
  virtual void client_wrote(std::string_view /*bytes*/, transport::ClientId /*client*/) {}
  /// The answer to what `client` wrote, due at once (written back to it by the output before the
  /// next epoch: PX4 waits 250 ms for an ACK). Default: none.
  [[nodiscard]] virtual std::string take_reply(transport::ClientId /*client*/) { return {}; }
  /// `client` went away: its half-read input is forgotten. Default: nothing.
  virtual void client_left(transport::ClientId /*client*/) {}
  /// Whether client_wrote() reads the bytes (a u-blox session) rather than ignoring them. Default: no.
  [[nodiscard]] virtual bool reads_client_input() const { return false; }
};

/// The configured NMEA sentences (nmea/sentences.hpp), in receiver order. Ignores client input.
class NmeaEncoder final : public Encoder {
 public:
  explicit NmeaEncoder(nmea::FormatOptions options) : options_(std::move(options)) {}
  void encode(const nmea::Fix& fix, std::string& out) override;

 private:
  nmea::FormatOptions options_;
  nmea::SatelliteTextMemo memo_;  ///< GSA/GSV text reused while the sky is unchanged
};

}  // namespace gpsemu
