// What a receiver's protocol asked the emulator for (protocol::ReceiverProtocol::take_effects(): a
// u-blox client's CFG-RATE, CFG-PRT baud, CFG-RST), applied to the running receiver at its next
// epoch, after the loop has serviced the client and written the answer, and the receiver's serial
// line as a protocol with a TX buffer (a u-blox) sees it:
// - a solution period: the receiver's epochs follow its grid from the epoch after
//   (receiver_schedule.hpp), whatever --rate is; the other receivers of a fleet and the PPS line
//   keep theirs;
// - a baud: each serial output of the receiver drains what is queued (the ACK leaves at the old
//   rate), then changes its termios speed;
// - after either, the line budget is checked again: when the widest epoch no longer fits the
//   line in one solution period, a warning says so and which baud would carry it;
// - each epoch on a serial line (ReceiverLine): what the line carries in the solution period goes
//   out, whole messages in order; a message that does not fit is dropped whole, as a u-blox's TX
//   buffer overflows, and counted (logged once, then at most every 10 s). A pty or socket has no
//   line limit (for a u-blox it is UART1, its baud recorded, docs/ublox.md "Ports");
// - a cold start: the receiver model starts again at the epoch (its --cold-start phases replay).
// The lines saying so (rate, baud, cold start, the line check) are rate-limited per receiver
// (emulator/common/log_limit.hpp): a client toggling CFG-RATE or flooding CFG-RST writes a few lines a
// second, with the count of those suppressed. Nothing here names a protocol.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "emulator/common/log_limit.hpp"
#include "emulator/model/time.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/receiver_schedule.hpp"
#include "transport/output.hpp"

namespace gpsemu {

/// The widest epoch of `channel`'s protocol now (the model's worst-case sky).
[[nodiscard]] std::size_t widest_epoch_bytes(const Channel& channel);

/// A receiver's serial line: its speed and what its protocol's TX buffer dropped.
struct ReceiverLine {
  std::uint32_t baud = 0;      ///< the slowest serial output's (bits per second); 0: no serial output
  protocol::LineDrops dropped;  ///< messages (and bytes) the line could not carry
  /// The TX-drop lines: the first at once, then at most one every 10 s (the totals so far).
  LogLimit tx_drop_log{1, std::chrono::seconds(10)};
  LogLimit effect_log{5};  ///< the effect lines of this receiver: at most 5 a second
};

/// The line of a receiver with `outputs`.
[[nodiscard]] ReceiverLine line_of(const std::vector<std::unique_ptr<transport::Output>>& outputs);

/// Applies the effects `channel`'s protocol holds at epoch `t`, with `outputs` the receiver's
/// outputs, `schedule` its epochs, `line` its serial line, `who` prefixing log lines.
void apply_protocol_effects(Channel& channel, const std::vector<std::unique_ptr<transport::Output>>& outputs,
                            ReceiverSchedule& schedule, ReceiverLine& line, UtcNs t, const std::string& who);

/// Cuts `channel`'s epoch bytes to what `line` carries in `period` (whole messages), counts and
/// logs what was dropped. Nothing without a serial line.
void fit_epoch_to_line(Channel& channel, std::chrono::nanoseconds period, ReceiverLine& line, const std::string& who);

/// One summary line of what the clients of `channel`'s protocol wrote and what they were answered
/// (empty for a protocol that reads no input).
[[nodiscard]] std::string client_input_summary(const Channel& channel);

/// One summary line of what `line` dropped (empty when nothing was).
[[nodiscard]] std::string tx_drops_summary(const Channel& channel, const ReceiverLine& line);

}  // namespace gpsemu
