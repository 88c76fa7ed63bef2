// A live session written down and taken back: each live event the control socket applied (a fault
// or a clear, faults/control.hpp) is recorded in the --tee file before its epoch's bytes as
//
//   # fault +12.300000000 2024-05-01T00:00:12.300Z {"fault":"jam","db":25,"receiver":0}
//
// (seconds after the first epoch, the epoch's time, the request), and `--scenario TEE_FILE` turns
// those lines back into faults at the same epochs: the same seed and --start-time then give the
// session's bytes again, without anyone at the socket.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "emulator/faults/fault.hpp"
#include "emulator/faults/fault_timeline.hpp"

namespace gpsemu::faults {

/// The line for `event`, without '\n'.
[[nodiscard]] std::string tee_event_line(const AppliedEvent& event);

/// Whether `text` is a --tee file (a line begins with "# sent " or "# fault +").
[[nodiscard]] bool looks_like_tee(std::string_view text);

/// The faults of a --tee file's "# fault" lines, in order: a fault starts at its epoch and lasts
/// its duration, a clear ends the faults of its kind (and receiver) still on at its epoch. Other
/// lines are skipped. Throws std::invalid_argument naming the line ("line 12: ...").
[[nodiscard]] std::vector<Fault> faults_from_tee(std::string_view text);

}  // namespace gpsemu::faults
