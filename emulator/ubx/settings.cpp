// Receiver settings and their power-up values (see settings.hpp).
#include "emulator/ubx/settings.hpp"

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/cfg_key_catalogue.hpp"
#include "emulator/ubx/messages.hpp"

namespace gpsemu::ubx {
namespace {

constexpr std::uint8_t kNmeaClass = 0xF0;
constexpr std::string_view kNmeaPrefix = "NMEA-";  // the message table's names of class 0xF0

std::string default_nav5() {
  std::string p;
  put_u2(p, 0xFFFF);   // mask: every parameter (as a poll answers)
  put_u1(p, 0);        // dynModel: portable
  put_u1(p, 3);        // fixMode: auto 2-D/3-D
  put_i4(p, 0);        // fixedAlt (0.01 m)
  put_u4(p, 10000);    // fixedAltVar (0.0001 m^2)
  put_i1(p, 5);        // minElev (degrees)
  put_u1(p, 0);        // drLimit (s)
  put_u2(p, 250);      // pDop (0.1)
  put_u2(p, 250);      // tDop (0.1)
  put_u2(p, 100);      // pAcc (m)
  put_u2(p, 300);      // tAcc (m)
  put_u1(p, 0);        // staticHoldThresh (cm/s)
  put_u1(p, 60);       // dgnssTimeout (s)
  put_u1(p, 0);        // cnoThreshNumSVs
  put_u1(p, 0);        // cnoThresh (dBHz)
  put_zeros(p, 2);
  put_u2(p, 0);        // staticHoldMaxDist (m)
  put_u1(p, 0);        // utcStandard: automatic
  put_zeros(p, 5);
  return p;
}

std::string default_gnss() {
  struct Block {
    std::uint8_t gnss_id, reserved_channels, max_channels;
    std::uint32_t flags;  // enable bit 0, signal mask bits 16-23
  };
  constexpr std::array<Block, 7> blocks = {{{0, 8, 16, 0x01010001}, {1, 1, 3, 0x01010001}, {2, 4, 8, 0x01010001},
                                            {3, 8, 16, 0x01010000}, {4, 0, 8, 0x03010000}, {5, 0, 3, 0x05010001},
                                            {6, 8, 14, 0x01010001}}};
  std::string p;
  put_u1(p, 0);   // msgVer
  put_u1(p, 32);  // numTrkChHw
  put_u1(p, 32);  // numTrkChUse
  put_u1(p, static_cast<std::uint32_t>(blocks.size()));
  for (const Block& b : blocks) {
    put_u1(p, b.gnss_id);
    put_u1(p, b.reserved_channels);
    put_u1(p, b.max_channels);
    put_u1(p, 0);
    put_u4(p, b.flags);
  }
  return p;
}

std::string default_sbas() {
  std::string p;
  put_u1(p, 0x01);  // mode: enabled
  put_u1(p, 0x03);  // usage: range, diffCorr
  put_u1(p, 3);     // maxSBAS
  put_u1(p, 0);     // scanmode2
  put_u4(p, 0);     // scanmode1: all PRNs
  return p;
}

/// Generation-9 keys without a modelled effect that drivers read back (CFG-VALGET), with the
/// values of a factory-default M9/F9.
struct DefaultKey {
  std::string_view name;
  std::uint64_t value;
};
constexpr std::array<DefaultKey, 20> kDefaultKeys = {{
    {"CFG-TMODE-MODE", 0},  // disabled
    {"CFG-UART1-STOPBITS", 1},  // 1
    {"CFG-UART1-DATABITS", 0},  // 8
    {"CFG-UART1-PARITY", 0},  // none
    {"CFG-UART1-ENABLED", 1},
    {"CFG-NAVSPG-INFIL_MINCNO", 6},  // dBHz
    {"CFG-ODO-USE_ODO", 0},
    {"CFG-ODO-USE_COG", 0},
    {"CFG-ODO-OUTLPVEL", 0},
    {"CFG-ODO-OUTLPCOG", 0},
    {"CFG-ITFM-ENABLE", 0},
    {"CFG-NAVHPG-DGNSSMODE", 3},  // RTK fixed
    {"CFG-SIGNAL-GPS_ENA", 1},
    {"CFG-SIGNAL-GPS_L1CA_ENA", 1},
    {"CFG-SIGNAL-SBAS_ENA", 1},
    {"CFG-SIGNAL-GAL_ENA", 1},
    {"CFG-SIGNAL-BDS_ENA", 1},
    {"CFG-SIGNAL-QZSS_ENA", 1},
    {"CFG-SIGNAL-GLO_ENA", 1},
    {"CFG-SIGNAL-GLO_L1_ENA", 1},
}};

}  // namespace

std::uint8_t Settings::rate(MessageId id, Port port) const {
  const auto it = rates.find(id);
  return it == rates.end() ? 0 : it->second[static_cast<std::size_t>(port)];
}

void Settings::set_rate(MessageId id, Port port, std::uint8_t rate) {
  if (rate == 0 && !rates.contains(id)) return;
  rates[id][static_cast<std::size_t>(port)] = rate;
}

Settings start_settings(const StartSettings& start) {
  Settings s;
  s.meas_period_ms = static_cast<std::uint16_t>(start.measurement_period.count());
  for (std::size_t i = 0; i < port_count; ++i) {
    s.ports[i] = PortSettings{};
    if (!model_info(start.model).rtcm_input) s.ports[i].in_proto_mask &= static_cast<std::uint16_t>(~proto_rtcm3);
  }
  const std::uint32_t default_baud = model_info(start.model).default_baud;
  s.ports[static_cast<std::size_t>(Port::uart1)].baud = default_baud;
  s.ports[static_cast<std::size_t>(Port::uart2)].baud = default_baud;
  s.ports[static_cast<std::size_t>(start.port)].baud = start.baud != 0 ? start.baud : default_baud;
  if (start.port == Port::usb) s.ports[static_cast<std::size_t>(Port::usb)].baud = 0;
  // NMEA sentences on at start on every port (as a factory-default u-blox), UBX on the client's.
  start.sentences.for_each([&](nmea::SentenceType type) {
    const auto id = nmea_message(type);
    if (!id) return;  // HDT, THS: not a u-blox message
    for (const Port p : {Port::i2c, Port::uart1, Port::uart2, Port::usb, Port::spi}) s.set_rate(*id, p, 1);
  });
  for (const MessageId id : start.ubx_messages) s.set_rate(id, start.port, 1);
  s.nav5 = default_nav5();
  s.gnss = default_gnss();
  s.sbas = default_sbas();
  if (model_info(start.model).key_value_config) {
    for (const DefaultKey& k : kDefaultKeys) s.other_keys[key_id(k.name)] = k.value;
  }
  return s;
}

std::optional<MessageId> nmea_message(nmea::SentenceType type) {
  return nmea_message_from_name(nmea::sentence_name(type));
}

std::optional<nmea::SentenceType> sentence_of(MessageId id) {
  const MessageRow* row = id.msg_class == kNmeaClass ? find_message(id) : nullptr;
  if (row == nullptr) return std::nullopt;
  return nmea::sentence_type_from_name(row->name.substr(kNmeaPrefix.size()));
}

std::optional<MessageId> nmea_message_from_name(std::string_view name) {
  const MessageRow* row = find_message(std::string(kNmeaPrefix) + std::string(name));
  if (row == nullptr || row->id.msg_class != kNmeaClass) return std::nullopt;
  return row->id;
}

}  // namespace gpsemu::ubx
