// Generation-9 configuration keys over Settings (see cfg_keys.hpp).
#include "emulator/ubx/cfg_keys.hpp"

#include <array>

#include "emulator/ubx/cfg_key_catalogue.hpp"
#include "emulator/ubx/cfg_legacy.hpp"

namespace gpsemu::ubx {
namespace {

/// CFG-MSGOUT keys: the I2C key of each message; UART1, UART2, USB, SPI follow at +1..+4.
struct MsgOut {
  MessageId id;
  std::uint32_t i2c_key;
};
constexpr std::array<MsgOut, 40> kMsgOut = {{
    {msg::nav_sol, 0x20910001},      {msg::nav_svinfo, 0x2091000B},  {msg::nav_sbas, 0x2091006A},
    {msg::nav_pvt, 0x20910006},      {msg::nav_posllh, 0x20910029},  {msg::nav_velned, 0x20910042},
    {msg::nav_status, 0x2091001A},   {msg::nav_dop, 0x20910038},     {msg::nav_sat, 0x20910015},
    {msg::nav_timeutc, 0x2091005B},  {msg::nav_timegps, 0x20910047}, {msg::nav_cov, 0x20910083},
    {msg::nav_posecef, 0x20910024},  // NAV-POSECEF
    {msg::nav_velecef, 0x2091003D},  // NAV-VELECEF
    {msg::nav_hpposllh, 0x20910033},
    {msg::nav_clock, 0x20910065},
    {msg::nav_timels, 0x20910060},
    {msg::nav_svin, 0x20910088},
    {msg::nav_relposned, 0x2091008D},
    {msg::nav_sig, 0x20910345},
    {msg::nav_eoe, 0x2091015F},      // NAV-EOE
    {{0x02, 0x13}, 0x20910231},      // RXM-SFRBX
    {{0x02, 0x15}, 0x209102A4},      // RXM-RAWX
    {{0x02, 0x32}, 0x20910268},      // RXM-RTCM
    {msg::mon_hw, 0x209101B4},
    {msg::mon_hw2, 0x209101B9},
    {msg::mon_rf, 0x20910359},
    {{0xF0, 0x00}, 0x209100BA},      // NMEA GGA
    {{0xF0, 0x01}, 0x209100C9},      // GLL
    {{0xF0, 0x02}, 0x209100BF},      // GSA
    {{0xF0, 0x03}, 0x209100C4},      // GSV
    {{0xF0, 0x04}, 0x209100AB},      // RMC
    {{0xF0, 0x05}, 0x209100B0},      // VTG
    {{0xF0, 0x06}, 0x209100CE},      // GRS
    {{0xF0, 0x07}, 0x209100D3},      // GST
    {{0xF0, 0x08}, 0x209100D8},      // ZDA
    {{0xF0, 0x09}, 0x209100DD},      // GBS
    {{0xF0, 0x0A}, 0x209100A6},      // DTM
    {{0xF0, 0x0D}, 0x209100B5},      // GNS
    {{0xF0, 0x0F}, 0x209100E7},      // VLW
}};

/// CFG-NAVSPG keys stored in the CFG-NAV5 payload: key -> byte offset.
struct Nav5Key {
  std::uint32_t key;
  std::size_t offset;
};
constexpr std::array<Nav5Key, 5> kNav5Keys = {{{0x20110011, 3},    // FIXMODE
                                               {0x20110021, 2},    // DYNMODEL
                                               {0x201100A4, 12},   // INFIL_MINELEV
                                               {0x201100C4, 23},   // CONSTR_DGNSSTO
                                               {0x2011001C, 30}}}; // UTCSTANDARD

const Nav5Key* nav5_key(std::uint32_t key) {
  for (const Nav5Key& n : kNav5Keys) {
    if (n.key == key) return &n;
  }
  return nullptr;
}

std::optional<MsgOut> msgout_of_key(std::uint32_t key, Port& port) {
  for (const MsgOut& m : kMsgOut) {
    if (key >= m.i2c_key && key <= m.i2c_key + 4) {
      port = static_cast<Port>(key - m.i2c_key);
      return m;
    }
  }
  return std::nullopt;
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

std::optional<std::uint32_t> msgout_key(MessageId id, Port port) {
  for (const MsgOut& m : kMsgOut) {
    if (m.id == id) return m.i2c_key + static_cast<std::uint32_t>(port);
  }
  return std::nullopt;
}

std::optional<MessageId> msgout_message(std::uint32_t key) {
  Port port = Port::i2c;
  if (const auto m = msgout_of_key(key, port)) return m->id;
  return std::nullopt;
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
  for (const Nav5Key& n : kNav5Keys) {
    if (n.key == key) return static_cast<std::uint8_t>(s.nav5[n.offset]);
  }
  Port port = Port::i2c;
  if (const auto m = msgout_of_key(key, port)) return s.rate(m->id, port);
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
  Port port = Port::i2c;
  if (msgout_of_key(key, port)) return value <= 255;
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
  for (const Nav5Key& n : kNav5Keys) f(n.key);
  for (const MsgOut& m : kMsgOut) {
    for (std::uint32_t p = 0; p < 5; ++p) f(m.i2c_key + p);
  }
}

std::optional<std::pair<MessageId, Port>> msgout_of(std::uint32_t key) {
  Port port = Port::i2c;
  if (const auto m = msgout_of_key(key, port)) return std::pair{m->id, port};
  return std::nullopt;
}

}  // namespace gpsemu::ubx
