// Generation-9 configuration keys over Settings (see cfg_keys.hpp).
#include "emulator/ubx/cfg_keys.hpp"

#include <array>

#include "emulator/ubx/cfg_key_catalogue.hpp"
#include "emulator/ubx/cfg_legacy.hpp"
#include "emulator/ubx/messages.hpp"

namespace gpsemu::ubx {
namespace {

/// CFG-NAVSPG keys stored in the CFG-NAV5 payload: key -> byte offset.
struct Nav5Key {
  std::uint32_t key;
  std::size_t offset;
};
const std::array<Nav5Key, 5>& nav5_keys() {
  static const std::array<Nav5Key, 5> keys = {{{key_id("CFG-NAVSPG-FIXMODE"), 3},
                                               {key_id("CFG-NAVSPG-DYNMODEL"), 2},
                                               {key_id("CFG-NAVSPG-INFIL_MINELEV"), 12},
                                               {key_id("CFG-NAVSPG-CONSTR_DGNSSTO"), 23},
                                               {key_id("CFG-NAVSPG-UTCSTANDARD"), 30}}};
  return keys;
}

const Nav5Key* nav5_key(std::uint32_t key) {
  for (const Nav5Key& n : nav5_keys()) {
    if (n.key == key) return &n;
  }
  return nullptr;
}

/// CFG-<port>INPROT / OUTPROT-<protocol>: group 0x71..0x7A, item 1 UBX, 2 NMEA, 4 RTCM3X.
struct ProtoKey {
  Port port;
  bool input;
  std::uint16_t mask;
};
std::optional<ProtoKey> proto_of_key(std::uint32_t key) {
  const std::uint32_t group = (key >> 16) & 0xFF;
  const std::uint32_t item = key & 0xFFFF;
  if ((key >> 24) != 0x10 || group < 0x71 || group > 0x7A) return std::nullopt;
  constexpr std::array<Port, 5> ports = {Port::i2c, Port::uart1, Port::uart2, Port::usb, Port::spi};
  const std::uint16_t mask = item == 1 ? proto_ubx : item == 2 ? proto_nmea : item == 4 ? proto_rtcm3 : 0;
  if (mask == 0) return std::nullopt;
  return ProtoKey{ports[(group - 0x71) / 2], (group - 0x71) % 2 == 0, mask};
}

}  // namespace

std::size_t key_value_bytes(std::uint32_t key) {
  switch ((key >> 28) & 0x7) {
    case 1:
    case 2: return 1;
    case 3: return 2;
    case 4: return 4;
    case 5: return 8;
    default: return 0;
  }
}

std::optional<std::uint64_t> get_key(const Settings& s, std::uint32_t key) {
  if (key == key::rate_meas) return s.meas_period_ms;
  if (key == key::rate_nav) return s.nav_rate_cycles;
  if (key == key::rate_timeref) return s.time_ref;
  if (key == key::uart1_baudrate) return s.ports[static_cast<std::size_t>(Port::uart1)].baud;
  if (key == key::uart2_baudrate) return s.ports[static_cast<std::size_t>(Port::uart2)].baud;
  if (const auto proto = proto_of_key(key)) {
    const PortSettings& p = s.ports[static_cast<std::size_t>(proto->port)];
    return ((proto->input ? p.in_proto_mask : p.out_proto_mask) & proto->mask) != 0 ? 1 : 0;
  }
  if (const Nav5Key* n = nav5_key(key)) return static_cast<std::uint8_t>(s.nav5[n->offset]);
  if (const auto m = msgout_of(key)) return s.rate(m->first, m->second);
  const auto it = s.other_keys.find(key);
  if (it != s.other_keys.end()) return it->second;
  return std::nullopt;
}

bool key_accepts(std::uint32_t key, std::uint64_t value) {
  if (key_value_bytes(key) == 0 || !is_known_key(key)) return false;
  if (key == key::rate_meas) return value >= min_meas_period_ms;
  if (key == key::rate_nav) return value >= 1 && value <= 127;
  if (key == key::rate_timeref) return value <= 5;
  if (key == key::uart1_baudrate || key == key::uart2_baudrate) return is_supported_baud(value);
  if (key == key::navspg_dynmodel) return is_dyn_model(value);
  if (key == key::navspg_fixmode) return value >= 1 && value <= 3;
  if (msgout_of(key)) return value <= 255;
  return true;
}

bool set_key(Settings& s, std::uint32_t key, std::uint64_t value) {
  if (!key_accepts(key, value)) return false;
  if (key == key::rate_meas) {
    s.meas_period_ms = static_cast<std::uint16_t>(value);
  } else if (key == key::rate_nav) {
    s.nav_rate_cycles = static_cast<std::uint16_t>(value);
  } else if (key == key::rate_timeref) {
    s.time_ref = static_cast<std::uint16_t>(value);
  } else if (key == key::uart1_baudrate || key == key::uart2_baudrate) {
    s.ports[static_cast<std::size_t>(key == key::uart1_baudrate ? Port::uart1 : Port::uart2)].baud =
        static_cast<std::uint32_t>(value);
  } else if (const auto proto = proto_of_key(key)) {
    PortSettings& p = s.ports[static_cast<std::size_t>(proto->port)];
    std::uint16_t& mask = proto->input ? p.in_proto_mask : p.out_proto_mask;
    mask = static_cast<std::uint16_t>(value != 0 ? (mask | proto->mask) : (mask & ~proto->mask));
  } else if (const Nav5Key* n = nav5_key(key)) {
    s.nav5[n->offset] = static_cast<char>(value & 0xFF);
  } else if (const auto m = msgout_of(key)) {
    s.set_rate(m->first, m->second, static_cast<std::uint8_t>(value));
  } else {
    s.other_keys[key] = value;
  }
  return true;
}

void for_each_modelled_key(const std::function<void(std::uint32_t)>& f) {
  for (const std::uint32_t k : {key::rate_meas, key::rate_nav, key::rate_timeref, key::uart1_baudrate, key::uart2_baudrate}) f(k);
  for (std::uint32_t group = 0x71; group <= 0x7A; ++group) {
    for (const std::uint32_t item : {1u, 2u, 4u}) f(0x10000000u | (group << 16) | item);
  }
  for (const Nav5Key& n : nav5_keys()) f(n.key);
  for (const MessageRow& row : message_table()) {
    for (std::size_t p = 0; p < 5; ++p) {
      if (const auto k = msgout_key(row.id, static_cast<Port>(p))) f(*k);
    }
  }
}

}  // namespace gpsemu::ubx
