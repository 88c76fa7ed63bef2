// The bytes of one epoch: every configured sentence for one Fix, in receiver order, ready for a
// single write.
#pragma once

#include <string>

#include "nmea/fix.hpp"

namespace gpsemu {

/// Writes the epoch's sentences (options.sentences, in receiver order: RMC VTG GGA GSA GSV GLL GST
/// ZDA) to `out` (cleared first; its capacity is reused).
void format_epoch(const nmea::Fix& fix, const nmea::FormatOptions& options, std::string& out);

}  // namespace gpsemu
