#include "emulator/pipeline/encoder.hpp"

#include "nmea/sentences.hpp"

namespace gpsemu {

void NmeaEncoder::encode(const nmea::Fix& fix, std::string& out) { nmea::append_epoch(fix, options_, out, memo_); }

}  // namespace gpsemu
