#include "emulator/model/sky/profile.hpp"

#include <algorithm>

namespace gpsemu::sky {

using S = nmea::GnssSystem;

ReceiverProfile profile_of(ubx::ReceiverModel model) {
  ReceiverProfile p;
  switch (model) {
    case ubx::ReceiverModel::generic:
    case ubx::ReceiverModel::ublox_m8n:
      p.systems = {S::gps, S::glonass, S::qzss, S::sbas};
      p.channels = 72;
      p.uere_m = 1.6;
      break;
    case ubx::ReceiverModel::ublox_m9n:
      p.systems = {S::gps, S::glonass, S::galileo, S::beidou, S::qzss, S::sbas};
      p.channels = 92;
      p.uere_m = 1.3;
      break;
    case ubx::ReceiverModel::ublox_m10:
      // Four concurrent systems (GPS, GLONASS, Galileo, BeiDou) and QZSS, SBAS; single band, as the
      // M9N, with the lower power of the M10 platform.
      p.systems = {S::gps, S::glonass, S::galileo, S::beidou, S::qzss, S::sbas};
      p.channels = 72;
      p.uere_m = 1.3;
      break;
    case ubx::ReceiverModel::ublox_f9p:
      p.systems = {S::gps, S::glonass, S::galileo, S::beidou, S::qzss, S::sbas};
      p.channels = 184;
      p.dual_band = true;
      p.uere_m = 1.0;
      break;
  }
  return p;
}

}  // namespace gpsemu::sky
