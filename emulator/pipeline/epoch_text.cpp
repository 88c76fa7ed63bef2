#include "emulator/pipeline/epoch_text.hpp"

#include "nmea/sentences.hpp"

namespace gpsemu {

void format_epoch(const nmea::Fix& fix, const nmea::FormatOptions& options, std::string& out) {
  out.clear();
  nmea::append_epoch(fix, options, out);
}

}  // namespace gpsemu
