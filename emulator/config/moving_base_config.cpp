// A fleet's moving-base pair (see fleet_config.hpp: link_moving_base_pairs, docs/heading.md).
#include <cstddef>
#include <optional>

#include <fmt/format.h>

#include "emulator/config/config.hpp"
#include "emulator/config/fleet_config.hpp"

namespace gpsemu {

void link_moving_base_pairs(std::vector<ReceiverSettings>& fleet) {
  std::optional<std::size_t> base;
  bool rovers = false;
  for (std::size_t i = 0; i < fleet.size(); ++i) {
    const heading::Role role = fleet[i].moving_base.role;
    if (role == heading::Role::rover) rovers = true;
    if (role != heading::Role::moving_base) continue;
    if (base) {
      throw ConfigError(fmt::format("role: receivers {} and {} are both moving-base: a fleet has one moving base "
                                    "(its rovers measure against it)", *base, i));
    }
    base = i;
  }
  if (!rovers) return;
  if (!base) throw ConfigError("role: a rover needs a receiver with role = \"moving-base\" in the same fleet");
  for (std::size_t i = 0; i < fleet.size(); ++i) {
    heading::MovingBaseOptions& mb = fleet[i].moving_base;
    if (mb.role != heading::Role::rover) continue;
    if (fleet[i].protocol == Protocol::nmea) {
      throw ConfigError(fmt::format("role: receiver {} is a rover: it reports NAV-RELPOSNED, so it needs protocol = "
                                    "\"ubx\" or \"nmea+ubx\"", i));
    }
    mb.base_antenna = fleet[*base].moving_base.antenna;
    const heading::Ned b = heading::baseline_ned(mb.base_antenna, mb.antenna, 0.0);
    if (b.north_m == 0.0 && b.east_m == 0.0 && b.down_m == 0.0) {
      throw ConfigError(fmt::format("antenna-offset: receiver {} (rover) and receiver {} (moving-base) have the same "
                                    "antenna offset: give them their places on the vehicle (no baseline, no heading)",
                                    i, *base));
    }
  }
}

}  // namespace gpsemu
