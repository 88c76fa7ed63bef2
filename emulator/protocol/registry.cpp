// Which protocol a receiver speaks (see registry.hpp).
#include "emulator/protocol/registry.hpp"

#include <chrono>
#include <cmath>
#include <optional>

#include "emulator/config/validate.hpp"
#include "emulator/protocol/nmea_protocol.hpp"
#include "emulator/protocol/ublox/state_file.hpp"
#include "emulator/protocol/ublox/ublox_protocol.hpp"
#include "nmea/line_budget.hpp"

namespace gpsemu::protocol {
namespace {

// The u-blox port's start settings (--protocol ubx / nmea+ubx): --receiver's model, the period of
// --rate, the sentences of --sentences (ubx: none unless given), NAV-PVT every epoch, the baud of
// a serial output (the accuracies, sAcc included, are the epoch's).
ubx::SessionSettings ublox_settings(const ReceiverSettings& receiver, const ReceiverOptions& /*options*/,
                                    const TimelineSettings& timeline) {
  const bool factory = factory_state(receiver);
  ubx::SessionSettings s;
  s.start.model = receiver.receiver_model;
  s.start.measurement_period = std::chrono::milliseconds{std::llround(1000.0 / timeline.rate_hz)};
  s.start.sentences = receiver.protocol == Protocol::ubx && !receiver.sentences_given ? nmea::SentenceSet{}
                                                                                     : receiver.format.sentences;
  if (!factory) s.start.ubx_messages = {ubx::msg::nav_pvt};  // from the factory: NMEA alone until a driver asks
  for (const transport::OutputSpec& spec : receiver.outputs) {
    if (spec.kind == transport::OutputKind::serial) {
      const int fallback = factory ? 0 : nmea::kDefaultBaud;  // 0: the model's default baud
      s.start.baud = static_cast<std::uint32_t>(spec.baud_bps != 0 ? spec.baud_bps : fallback);
    }
  }
  if (receiver.receiver_state) s.stored = read_receiver_state(*receiver.receiver_state, receiver.receiver_model);
  s.format = receiver.format;
  s.seed = receiver.seed;
  return s;
}

}  // namespace

std::shared_ptr<const ProtocolSpec> protocol_for(const ReceiverSettings& receiver, const ReceiverOptions& options,
                                                 const TimelineSettings& timeline, const ReplaceFile& replace_file) {
  if (receiver.protocol == Protocol::nmea && !factory_state(receiver)) return nmea_protocol(receiver.format);
  std::optional<StateFile> state;
  if (receiver.receiver_state) state = StateFile{*receiver.receiver_state, replace_file};
  return ublox_protocol(ublox_settings(receiver, options, timeline), std::move(state));
}

int factory_baud(const ReceiverSettings& receiver) {
  return factory_state(receiver) ? static_cast<int>(facts_of(receiver.receiver_model).default_baud) : 0;
}

}  // namespace gpsemu::protocol
