#include "emulator/epoch_text.hpp"

#include "nmea/sentences.hpp"

namespace gpsemu {

void format_epoch(const nmea::Fix& fix, const nmea::FormatOptions& options, std::string& out) {
  out.clear();
  out += nmea::format_gga(fix, options);
  out += nmea::format_rmc(fix, options);
}

}  // namespace gpsemu
