// Which protocol a receiver speaks: the one place that chooses among the implementations of the
// receiver protocol interface (receiver_protocol.hpp) from a receiver's settings. The pipeline
// asks here and never names a protocol; a new protocol is one implementation plus its line here.
#pragma once

#include <cstdint>
#include <memory>

#include "emulator/config/settings.hpp"
#include "emulator/protocol/receiver_protocol.hpp"
#include "emulator/protocol/ublox/state_file.hpp"

namespace gpsemu::protocol {

/// The protocol of `receiver` (its noise and sky as `options` resolve them, on `timeline`): a
/// u-blox port for --protocol ubx or nmea+ubx and for a receiver in its factory state, else the
/// NMEA sentences of its format. A u-blox writes its --receiver-state with `replace_file` (the OS
/// layer's posix::replace_file). Throws std::invalid_argument when --receiver-state cannot be read.
[[nodiscard]] std::shared_ptr<const ProtocolSpec> protocol_for(const ReceiverSettings& receiver,
                                                               const ReceiverOptions& options,
                                                               const TimelineSettings& timeline,
                                                               const ReplaceFile& replace_file);

/// The baud of a serial output given none: the receiver model's default in its factory state,
/// else 0 (the emulator's default applies).
[[nodiscard]] int factory_baud(const ReceiverSettings& receiver);

}  // namespace gpsemu::protocol
