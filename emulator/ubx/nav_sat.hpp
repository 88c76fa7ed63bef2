// The satellite messages of a u-blox, from the fix's satellites in view (the sky GSV lists):
// NAV-SAT (protocol 15+: every model), NAV-SVINFO (u-blox 8 and older; removed in protocol 27)
// and NAV-SIG (protocol 27+: one entry per tracked signal; the F9P tracks two bands). A
// satellite's system and number come from its `system` and `sv_id`; a satellite without an
// sv_id (0) is read from its NMEA id: 1-32 GPS, 33-64 SBAS (PRN 120-151), 65-96 GLONASS.
// Byte layouts: u-blox's interface descriptions (M8 protocol 18+, F9 HPG 1.32). Pure.
#pragma once

#include <cstdint>
#include <string>

#include "emulator/ubx/model.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::ubx {

/// A satellite as UBX numbers it: gnssId and the system's svId.
struct UbxSatId {
  std::uint8_t gnss_id = 0;
  std::uint8_t sv_id = 0;
};
[[nodiscard]] UbxSatId ubx_sat_id(const nmea::SatelliteInView& sat);
/// NAV-SVINFO's one-byte svid (u-blox 8 numbering): GPS 1-32, SBAS 120-158, Galileo 211-246,
/// BeiDou B1-B5 159-163 and B6-B37 33-64, QZSS 193-202, GLONASS 65-96; 255 for none of them.
[[nodiscard]] std::uint8_t svinfo_svid(UbxSatId id);
/// GLONASS frequency channel (-7..+6) of orbital slot 1-24 (0 for another slot).
[[nodiscard]] int glonass_frequency_channel(int slot);

/// NAV-SAT, 8 + 12 per satellite in view.
[[nodiscard]] std::string nav_sat(const nmea::Fix& fix);
/// NAV-SVINFO, 8 + 12 per satellite in view (chipGen 4: u-blox 8).
[[nodiscard]] std::string nav_svinfo(const nmea::Fix& fix);
/// NAV-SIG, 8 + 16 per signal of the tracked satellites (those with a C/N0): L1 on every model,
/// and with dual_band(model) the second band of GPS (L2 CL), GLONASS (L2 OF), Galileo (E5b I),
/// BeiDou (B2I) and QZSS (L2 CL), a few dB weaker.
[[nodiscard]] std::string nav_sig(const nmea::Fix& fix, ReceiverModel model);
/// Signals NAV-SIG lists for `fix` on `model`.
[[nodiscard]] int signal_count(const nmea::Fix& fix, ReceiverModel model);

}  // namespace gpsemu::ubx
