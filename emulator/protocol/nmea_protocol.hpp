// Plain NMEA (nmea/sentences.hpp): the configured sentences in receiver order, one epoch a fix.
// What a client writes is ignored (read and discarded by the output); it asks for no effect.
#pragma once

#include <memory>
#include <string>

#include "emulator/protocol/receiver_protocol.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::protocol {

class NmeaProtocol final : public ReceiverProtocol {
 public:
  explicit NmeaProtocol(nmea::FormatOptions options) : options_(std::move(options)) {}
  void encode(const ReceiverEpoch& epoch, std::string& out) override;
  [[nodiscard]] std::size_t widest_epoch_bytes(const Geometry& sky) const override;
  [[nodiscard]] std::string name() const override { return "NMEA"; }
  [[nodiscard]] std::string written() const override { return "NMEA"; }

 private:
  nmea::FormatOptions options_;
  nmea::SatelliteTextMemo memo_;  ///< GSA/GSV text reused while the sky is unchanged
};

/// The sentences of `options`.
[[nodiscard]] std::shared_ptr<const ProtocolSpec> nmea_protocol(nmea::FormatOptions options);

}  // namespace gpsemu::protocol
