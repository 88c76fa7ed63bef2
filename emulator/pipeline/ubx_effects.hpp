// What a u-blox client asked the emulator for (UbxEncoder::take_effects(): CFG-RATE, CFG-PRT baud,
// CFG-RST), applied to the running receiver at its next epoch, after the loop has serviced the
// client and written the answer, and the receiver's serial line as a u-blox's TX buffer sees it:
// - a solution period: the receiver's epochs follow it from the epoch after (receiver_schedule.hpp;
//   aligned to the week as a u-blox, at most the model's fastest navigation rate), whatever --rate
//   is; the other receivers of a fleet and the PPS line keep theirs;
// - a baud: each serial output of the receiver drains what is queued (the ACK leaves at the old
//   rate), then changes its termios speed;
// - after either, the line budget is checked again: when the widest epoch no longer fits the
//   line in one solution period, a warning says so and which baud would carry it;
// - each epoch on a serial line (UbxLine): what the line carries in the solution period goes out,
//   whole messages in order; a message that does not fit is dropped whole, as a u-blox's TX
//   buffer overflows, and counted (logged once, then at most every 10 s). A pty or socket has no
//   line limit (it is UART1, its baud recorded, docs/ublox.md "Ports");
// - a cold start: the receiver model starts again at the epoch (its --cold-start phases replay).
// The lines saying so (rate, baud, cold start, the line check) are rate-limited per receiver
// (transport/log_limit.hpp): a client toggling CFG-RATE or flooding CFG-RST writes a few lines a
// second, with the count of those suppressed.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "emulator/model/time.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/receiver_schedule.hpp"
#include "emulator/ubx/settings.hpp"
#include "emulator/ubx/tx_budget.hpp"
#include "nmea/fix.hpp"
#include "transport/log_limit.hpp"
#include "transport/output.hpp"

namespace gpsemu {

/// The widest epoch of a u-blox port with `settings`: the NMEA sentences on for `port` (written as
/// `format` says, for the satellites of `sky`: resolve_geometry's worst case by system), then the
/// UBX messages on.
[[nodiscard]] std::size_t widest_ubx_epoch_bytes(const nmea::FormatOptions& format, const ubx::Settings& settings,
                                                 ubx::Port port, ubx::ReceiverModel model, const Geometry& sky);
/// The widest epoch of `channel`'s u-blox port now (0 for an NMEA channel).
[[nodiscard]] std::size_t widest_ubx_epoch_bytes(const Channel& channel);

/// A u-blox receiver's serial line: its speed and what its TX buffer dropped.
struct UbxLine {
  std::uint32_t baud = 0;  ///< the slowest serial output's (bits per second); 0: no serial output
  ubx::TxDrops dropped;    ///< messages (and bytes) the line could not carry
  /// The TX-drop lines: the first at once, then at most one every 10 s (the totals so far).
  transport::LogLimit tx_drop_log{1, std::chrono::seconds(10)};
  transport::LogLimit effect_log{5};  ///< the effect lines of this receiver: at most 5 a second
};

/// The line of a receiver with `outputs`.
[[nodiscard]] UbxLine ubx_line_of(const std::vector<std::unique_ptr<transport::Output>>& outputs);

/// Applies the effects `channel`'s UBX encoder holds (none for an NMEA channel) at epoch `t`, with
/// `outputs` the receiver's outputs, `schedule` its epochs, `line` its serial line, `who` prefixing
/// log lines.
void apply_ubx_effects(Channel& channel, const std::vector<std::unique_ptr<transport::Output>>& outputs,
                       ReceiverSchedule& schedule, UbxLine& line, UtcNs t, const std::string& who);

/// Cuts `channel`'s epoch bytes to what `line` carries in `period` (whole messages), counts and
/// logs what was dropped. Nothing without a serial line.
void fit_epoch_to_line(Channel& channel, std::chrono::nanoseconds period, UbxLine& line, const std::string& who);

/// One summary line of what the client of `channel`'s u-blox wrote and what it was answered
/// (empty for an NMEA channel): frames, bad frames, sentences, ACK, NAK, polls folded into one
/// answer, effects a newer one replaced.
[[nodiscard]] std::string client_input_summary(const Channel& channel);

/// One summary line of what `line` dropped (empty when nothing was).
[[nodiscard]] std::string tx_drops_summary(const UbxLine& line);
/// One summary line of what `channel`'s u-blox configuration did not carry out: answers not sent
/// because the port's output excluded UBX, transactions begun and never applied, and the resets
/// that reloaded the layers (empty when none, or for an NMEA channel).
[[nodiscard]] std::string ubx_config_summary(const Channel& channel);

}  // namespace gpsemu
