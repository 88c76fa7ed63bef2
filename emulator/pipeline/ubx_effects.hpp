// What a u-blox client asked the emulator for (UbxEncoder::take_effects(): CFG-RATE, CFG-PRT baud,
// CFG-RST), applied to the running receiver at its next epoch, after the loop has serviced the
// client and written the answer:
// - a measurement period: the loop keeps --rate's period (the epoch grid is shared by every
//   receiver and the PPS line); the session's measurement grid thins the solutions to the asked
//   period when it is a multiple of the loop's; a shorter period (or one off the loop's grid) is
//   acknowledged, as a u-blox does, but solutions come on the loop's grid, with a warning;
// - a baud: each serial output of the receiver drains what is queued (the ACK leaves at the old
//   rate), then changes its termios speed, and the line budget is checked again (a warning when
//   the widest epoch no longer fits);
// - a cold start: the receiver model starts again at the epoch (its --cold-start phases replay).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "emulator/model/time.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/ubx/settings.hpp"
#include "nmea/fix.hpp"
#include "transport/output.hpp"

namespace gpsemu {

/// The widest epoch of a u-blox port with `settings`: the NMEA sentences on for `port` (written as
/// `format` says), then the UBX messages on.
[[nodiscard]] std::size_t widest_ubx_epoch_bytes(const nmea::FormatOptions& format, const ubx::Settings& settings,
                                                 ubx::Port port);

/// Applies the effects `channel`'s UBX encoder holds (none for an NMEA channel) at epoch `t`, with
/// `outputs` the receiver's outputs, the loop at `loop_rate_hz`, `who` prefixing log lines.
void apply_ubx_effects(Channel& channel, const std::vector<std::unique_ptr<transport::Output>>& outputs,
                       double loop_rate_hz, UtcNs t, const std::string& who);

}  // namespace gpsemu
