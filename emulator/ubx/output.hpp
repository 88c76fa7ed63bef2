// What a u-blox writes with each navigation solution, from its settings: the UBX messages and
// NMEA sentences due on the client's port (a message at rate n goes out with every n-th
// solution; none of a protocol the port does not output). A u-blox writes the epoch's NAV
// messages first, then its NMEA sentences, and ends the epoch with NAV-EOE when that is on (the
// recorded u-blox 8 and F9 streams of gpsd's regression logs; u-blox's interface description of
// NAV-EOE): append_solution() writes the NAV messages by class, then id (NAV-POSECEF, POSLLH,
// STATUS, DOP, SOL, PVT, VELECEF, VELNED, HPPOSLLH, TIMEGPS, TIMEUTC, CLOCK, TIMELS, SVINFO, SAT, COV,
// SIG, then MON-HW, MON-HW2, MON-RF), polled messages once more;
// the caller writes the NMEA sentences after them, then append_end_of_epoch(). Pure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "emulator/ubx/messages.hpp"
#include "emulator/ubx/nav.hpp"
#include "emulator/ubx/settings.hpp"
#include "nmea/sentence_set.hpp"

namespace gpsemu::ubx {

/// UBX messages this library encodes that are due with solution `solution_index` (0, 1, ...).
[[nodiscard]] std::vector<MessageId> due_messages(const Settings& s, Port port, std::uint64_t solution_index);
/// NMEA sentences gpsemu writes that are due with solution `solution_index`.
[[nodiscard]] nmea::SentenceSet due_sentences(const Settings& s, Port port, std::uint64_t solution_index);
/// RTCM3 messages one base epoch can bring to a port within one solution (1005/1006, MSM of five
/// systems, 1230, 4072.0 and 4072.1, one more): the RXM-RTCM reports the line budget counts.
inline constexpr std::size_t rtcm_messages_per_solution_budget = 10;
/// The most UBX bytes one solution can carry on `port` with these settings (every message that is
/// on, NAV-SAT with max_satellites, NAV-SIG with each of their signals on `model`, NAV-RELPOSNED
/// when on, and RXM-RTCM's reports of rtcm_messages_per_solution_budget messages when it is on and
/// the port takes RTCM3): the serial line budget's share of UBX.
[[nodiscard]] std::size_t widest_solution_ubx_bytes(const Settings& s, Port port,
                                                    ReceiverModel model = ReceiverModel::generic);
/// Appends the frames of the due UBX messages but NAV-EOE, then those of `polled` not already
/// written.
void append_solution(std::string& out, const Settings& s, Port port, std::uint64_t solution_index,
                     const nmea::Fix& fix, const NavExtras& extras, std::span<const MessageId> polled = {});
/// Appends NAV-EOE when it is due (or polled): the last bytes of the epoch, after its NMEA.
void append_end_of_epoch(std::string& out, const Settings& s, Port port, std::uint64_t solution_index,
                         const nmea::Fix& fix, std::span<const MessageId> polled = {});

}  // namespace gpsemu::ubx
