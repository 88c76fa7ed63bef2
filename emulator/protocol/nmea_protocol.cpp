#include "emulator/protocol/nmea_protocol.hpp"

#include "nmea/line_budget.hpp"

namespace gpsemu::protocol {

void NmeaProtocol::encode(const ReceiverEpoch& epoch, std::string& out) { nmea::append_epoch(epoch.fix, options_, out, memo_); }

std::size_t NmeaProtocol::widest_epoch_bytes(const Geometry& sky) const {
  return nmea::line_budget(options_, sky.in_view_by_system, sky.satellites_used, 1.0).bytes_per_epoch;
}

namespace {

class NmeaSpec final : public ProtocolSpec {
 public:
  explicit NmeaSpec(nmea::FormatOptions options) : options_(std::move(options)) {}
  [[nodiscard]] std::unique_ptr<ReceiverProtocol> make() const override {
    return std::make_unique<NmeaProtocol>(options_);
  }
  [[nodiscard]] std::size_t widest_epoch_bytes(const Geometry& sky) const override {
    return NmeaProtocol(options_).widest_epoch_bytes(sky);
  }

 private:
  nmea::FormatOptions options_;
};

}  // namespace

std::shared_ptr<const ProtocolSpec> nmea_protocol(nmea::FormatOptions options) {
  return std::make_shared<NmeaSpec>(std::move(options));
}

}  // namespace gpsemu::protocol
