// Many receivers in one process (a fleet, e.g. one per simulated vehicle): the shared receiver
// settings expanded, when the configuration loads, into one ReceiverSettings per receiver.
//
// - `--receivers N`: N receivers from the same settings. In `output` (each), `source` and `tee`,
//   `{i}` becomes the receiver's index 0..N-1 and `{B+i}` (B a whole number) becomes B + i, so
//   `--source udp:{5600+i} --output pty:/tmp/gps{i}` gives receiver 7 udp:5607 and pty:/tmp/gps7.
//   Receiver i's seed is seed + i.
// - `[[receiver]]` tables in the config file: one receiver per table, its keys overriding the
//   shared settings (defaults < file top level < command line < the receiver's table). A table
//   that sets `seed` gets that seed; otherwise receiver i gets seed + i.
//
// Two receivers, or two outputs (or an output and the tee) of one receiver, may not write to the
// same thing (pty link, file, serial device, stdout, tcp port, udp destination, tee file; paths
// compared after resolving them) nor listen on the same port: that is refused at start-up.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "emulator/config/config_options.hpp"

namespace gpsemu {

/// `text` with `{i}` replaced by `index` and `{B+i}` by B + index. Throws std::invalid_argument
/// naming `key` for any other `{...}` (or an unclosed `{`).
[[nodiscard]] std::string expand_receiver_template(const std::string& key, std::string_view text, int index);

/// One ReceiverSettings per receiver of `draft` (its tables, or `receivers`), in index order: the
/// table applied, derived values resolved (validate.hpp), templates expanded and the source and
/// output specs parsed. Throws ConfigError for a bad template, a bad table, two receivers sharing
/// an output or a source port (the message names both receivers and, for a setting without {i},
/// says to add it), one receiver naming one destination twice (the message names both), or a bad
/// spec.
[[nodiscard]] std::vector<ReceiverSettings> resolve_receivers(const ConfigDraft& draft);

/// Pairs a fleet's rover with its moving base (moving_base_config.cpp): each rover gets the base's
/// antenna offset. Throws ConfigError when there are rovers but not exactly one moving base, a
/// rover without UBX output (NAV-RELPOSNED), or a pair on one antenna (no baseline).
void link_moving_base_pairs(std::vector<ReceiverSettings>& fleet);

}  // namespace gpsemu
