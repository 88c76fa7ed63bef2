// A simulated RTK reference station (`gpsemu base`, docs/rtk.md): at each epoch, the RTCM3 a
// u-blox F9P base in survey-in-done / fixed mode writes once a second:
//
//   1005 (its antenna reference point, ECEF), or 1006 with the antenna height when one is given;
//   one MSM4 or MSM7 per system of its sky (1074/1077 GPS, 1084/1087 GLONASS, 1094/1097 Galileo,
//     1114/1117 QZSS, 1124/1127 BeiDou; the multiple message bit on all but the last), every
//     satellite the sky says it uses (above the elevation mask, strong enough) on L1 and L2;
//   1230 (GLONASS code-phase biases of the L1 C/A and L2 C/A signals observed: 0 m).
//
// The sky is the emulator's (model/sky.hpp: the real orbits of the embedded or --ephemeris
// navigation data at the station, C/N0 by elevation). The ranges come from the geometry: the
// satellite's ECEF position at transmission (one light-time iteration) rotated by the Earth's
// turn meanwhile (Sagnac), to the ARP; range rates from the satellite's velocity along the line
// of sight. No clocks, no atmosphere, no noise: the phase range equals the pseudorange. The
// emulated rover does not use the observations (it knows the truth), but RTKLIB and gpsd decode them
// and a real RTK engine sees a consistent, slowly changing geometry. Lock times count from the
// epoch a satellite was first observed. Deterministic given the settings, the seed and the time.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "emulator/model/geo.hpp"
#include "emulator/model/sky.hpp"
#include "emulator/model/time.hpp"
#include "emulator/rtk/rtcm3_messages.hpp"

namespace gpsemu::base {

struct BaseSettings {
  Geodetic arp{43.0725, -89.4125, 260.0};  ///< antenna reference point: degrees, degrees, metres above MSL
  std::uint16_t station_id = 0;            ///< DF003, 0..4095
  int msm = 4;                             ///< 4 or 7
  std::optional<double> antenna_height_m;  ///< given: 1006 with it (0..6.5535 m); else 1005
  std::vector<rtk::Gnss> systems{rtk::Gnss::gps, rtk::Gnss::glonass, rtk::Gnss::galileo, rtk::Gnss::qzss,
                                 rtk::Gnss::beidou};  ///< in output order; each with an MSM when it has satellites
  bool dual_band = true;                   ///< L1 and L2 signals (an F9P base), else L1 only
  std::shared_ptr<const sky::Orbits> orbits;  ///< empty: the embedded sky
  std::optional<double> elevation_mask_deg;   ///< empty: the F9P's
  std::uint64_t seed = 1;                     ///< the sky's C/N0 offsets
};

/// One epoch of the base.
struct BaseEpoch {
  std::string bytes;                   ///< the frames, in order
  std::vector<std::uint16_t> types;    ///< their message numbers
  int satellites = 0;                  ///< satellites observed (in the MSMs)
};

/// "GPS,GLONASS,Galileo,BeiDou,QZSS" (any case, any order, comma-separated) into systems in output
/// order. Throws std::invalid_argument naming the unknown name and the accepted ones.
[[nodiscard]] std::vector<rtk::Gnss> parse_systems(const std::string& text);

class BaseStation {
 public:
  /// Throws std::invalid_argument for an MSM other than 4 or 7, a station id above 4095 or an
  /// antenna height outside 0..6.5535 m.
  explicit BaseStation(const BaseSettings& settings);

  /// The epoch at UTC `t` (epochs in increasing time).
  [[nodiscard]] BaseEpoch epoch(UtcNs t);

  /// The ARP as 1005/1006 say it (ECEF metres, the station id, the antenna height).
  [[nodiscard]] const rtk::BasePosition& position() const { return position_; }

 private:
  BaseSettings settings_;
  rtk::BasePosition position_;
  Sky sky_;
  std::map<std::pair<int, int>, std::size_t> orbit_index_;  ///< (system, sv id) -> Orbits index
  std::map<std::pair<int, int>, UtcNs> first_seen_;         ///< lock times count from here
};

}  // namespace gpsemu::base
