// The moving base's RTCM 3 output, one epoch at a time (what an F9P moving base writes on the
// port its rover listens to, forwarded by the autopilot): 4072.0, then one MSM4 per system of the
// base's tracked satellites (1074 GPS, 1084 GLONASS, 1094 Galileo, 1114 QZSS, 1124 BeiDou; the
// multiple-message bit set on all but the last), then 1230 (GLONASS code-phase biases, none).
// Pure: the base's fix in, frames out.
//
// MSM4 (rtk/rtcm3_msm.hpp, the encoder `gpsemu base` shares): one L1/B1/E1/G1 signal a satellite.
// The ranges are geometric from the satellite's elevation and its orbit's radius (no clocks, no
// atmosphere), so a decoder sees plausible 64-90 ms ranges; the rover emulator does not use them.
// (`gpsemu base` computes its ranges from the orbits themselves: base/base_station.hpp.)
//
// 4072.0 is u-blox proprietary and undocumented; gpsemu writes message 4072, sub-type 0 (12 bits)
// and its own body: station ID (12), GPS TOW ms (30), the base antenna's ECEF X, Y, Z (38 bits
// each, 0.1 mm, as 1005). Only gpsemu's rover reads it: a real F9P rover would not.
#pragma once

#include <cstdint>
#include <string>

#include "nmea/fix.hpp"

namespace gpsemu::heading {

/// The MSM4 message number of a system (1074, 1084, 1094, 1114, 1124), 0 for SBAS.
[[nodiscard]] int msm4_message_number(nmea::GnssSystem system);

/// The frames of one epoch of the base: 4072.0, MSM4 per system with tracked satellites, 1230.
/// Nothing without a fix (the base has no position to send).
[[nodiscard]] std::string base_rtcm3_epoch(const nmea::Fix& base_fix, std::uint16_t station_id);

}  // namespace gpsemu::heading
