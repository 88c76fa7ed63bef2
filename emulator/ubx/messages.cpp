// The UBX message table (see messages.hpp).
#include "emulator/ubx/messages.hpp"

#include <algorithm>
#include <array>
#include <vector>

#include <fmt/format.h>

#include "emulator/ubx/cfg_key_catalogue.hpp"
#include "emulator/ubx/layouts.hpp"
#include "emulator/ubx/mon.hpp"
#include "emulator/ubx/nav_sat.hpp"
#include "emulator/ubx/relposned.hpp"

namespace gpsemu::ubx {
namespace {

using enum MessageRole;
using namespace models;

// Encoders of the messages that need less than the whole fix and extras.
std::string enc_posllh(const nmea::Fix& f, const NavExtras&) { return nav_posllh(f); }
std::string enc_posecef(const nmea::Fix& f, const NavExtras&) { return nav_posecef(f); }
std::string enc_dop(const nmea::Fix& f, const NavExtras&) { return nav_dop(f); }
std::string enc_hpposllh(const nmea::Fix& f, const NavExtras&) { return nav_hpposllh(f); }
std::string enc_svinfo(const nmea::Fix& f, const NavExtras&) { return nav_svinfo(f); }
std::string enc_sat(const nmea::Fix& f, const NavExtras&) { return nav_sat(f); }
std::string enc_relposned(const nmea::Fix& f, const NavExtras& x) { return nav_relposned(f, x.relpos); }
std::string enc_sig(const nmea::Fix& f, const NavExtras& x) { return nav_sig(f, x.model); }
std::string enc_eoe(const nmea::Fix& f, const NavExtras&) { return nav_eoe(f); }
std::string enc_mon_hw(const nmea::Fix&, const NavExtras& x) { return mon_hw(x.rf); }
std::string enc_mon_hw2(const nmea::Fix&, const NavExtras&) { return mon_hw2(); }
std::string enc_mon_rf(const nmea::Fix&, const NavExtras& x) { return mon_rf(x.rf, x.model); }

constexpr ModelSet m8_only = m8;
constexpr ModelSet gen9_rtcm = m9n | f9p;   // RTCM3 input reported (the M10, SPG 5.10, takes none)
constexpr ModelSet no_m10 = m8 | m9n | f9p; // gone in the M10 (SPG 5.10): the legacy CFG messages, NAV-SOL, MON-HW...

// clang-format off
const std::array<MessageRow, 54> kTable = {{
    {msg::nav_posecef, "NAV-POSECEF", all, solution, true, enc_posecef, layout::nav_posecef},
    {msg::nav_posllh, "NAV-POSLLH", all, solution, true, enc_posllh, layout::nav_posllh},
    {msg::nav_status, "NAV-STATUS", all, solution, true, nav_status, layout::nav_status},
    {msg::nav_dop, "NAV-DOP", all, solution, true, enc_dop, layout::nav_dop},
    {msg::nav_sol, "NAV-SOL", no_m10, solution, true, nav_sol, layout::nav_sol},
    {msg::nav_pvt, "NAV-PVT", all, solution, true, nav_pvt, layout::nav_pvt},
    {msg::nav_velecef, "NAV-VELECEF", all, solution, true, nav_velecef, layout::nav_velecef},
    {msg::nav_velned, "NAV-VELNED", all, solution, true, nav_velned, layout::nav_velned},
    {msg::nav_hpposllh, "NAV-HPPOSLLH", f9p, solution, true, enc_hpposllh, layout::nav_hpposllh},
    {msg::nav_timegps, "NAV-TIMEGPS", all, solution, true, nav_timegps, layout::nav_timegps},
    {msg::nav_timeutc, "NAV-TIMEUTC", all, solution, true, nav_timeutc, layout::nav_timeutc},
    {msg::nav_clock, "NAV-CLOCK", all, solution, true, nav_clock, layout::nav_clock},
    {msg::nav_timels, "NAV-TIMELS", all, solution, true, nav_timels, layout::nav_timels},
    {msg::nav_svinfo, "NAV-SVINFO", m8_only, solution, true, enc_svinfo, layout::nav_svinfo, layout::nav_svinfo_block},
    {msg::nav_sbas, "NAV-SBAS", m8 | m10, output, true},
    {msg::nav_sat, "NAV-SAT", all, solution, true, enc_sat, layout::nav_sat, layout::nav_sat_block},
    {msg::nav_cov, "NAV-COV", all, solution, true, nav_cov, layout::nav_cov},
    {msg::nav_svin, "NAV-SVIN", f9p, output, true},
    {msg::nav_relposned, "NAV-RELPOSNED", f9p, solution, true, enc_relposned, layout::nav_relposned},
    {msg::nav_sig, "NAV-SIG", generation9, solution, true, enc_sig, layout::nav_sig, layout::nav_sig_block},
    {msg::nav_eoe, "NAV-EOE", all, solution, true, enc_eoe, layout::nav_eoe},
    {{0x02, 0x13}, "RXM-SFRBX", all, output, true},
    {{0x02, 0x15}, "RXM-RAWX", no_m10, output, true},
    {msg::rxm_rtcm, "RXM-RTCM", gen9_rtcm, report, true, nullptr, layout::rxm_rtcm},
    {msg::ack_nak, "ACK-NAK", all, report, false},
    {msg::ack_ack, "ACK-ACK", all, report, false},
    {msg::cfg_prt, "CFG-PRT", no_m10, input, false},
    {msg::cfg_msg, "CFG-MSG", no_m10, input, false},
    {msg::cfg_rst, "CFG-RST", all, input, false},
    {msg::cfg_rate, "CFG-RATE", no_m10, input, false},
    {msg::cfg_cfg, "CFG-CFG", all, input, false},
    {msg::cfg_sbas, "CFG-SBAS", no_m10, input, false},
    {msg::cfg_nav5, "CFG-NAV5", no_m10, input, false},
    {msg::cfg_gnss, "CFG-GNSS", no_m10, input, false},
    {msg::cfg_valset, "CFG-VALSET", generation9, input, false},
    {msg::cfg_valget, "CFG-VALGET", generation9, input, false},
    {msg::cfg_valdel, "CFG-VALDEL", generation9, input, false},
    {msg::mon_ver, "MON-VER", all, poll, false, nullptr, layout::mon_ver, layout::mon_ver_block},
    {msg::mon_hw, "MON-HW", no_m10, solution, true, enc_mon_hw, layout::mon_hw},
    {msg::mon_hw2, "MON-HW2", no_m10, solution, true, enc_mon_hw2, layout::mon_hw2},
    {msg::mon_rf, "MON-RF", generation9, solution, true, enc_mon_rf, layout::mon_rf, layout::mon_rf_block},
    {{0xF0, 0x00}, "NMEA-GGA", all, output, true},
    {{0xF0, 0x01}, "NMEA-GLL", all, output, true},
    {{0xF0, 0x02}, "NMEA-GSA", all, output, true},
    {{0xF0, 0x03}, "NMEA-GSV", all, output, true},
    {{0xF0, 0x04}, "NMEA-RMC", all, output, true},
    {{0xF0, 0x05}, "NMEA-VTG", all, output, true},
    {{0xF0, 0x06}, "NMEA-GRS", all, output, true},
    {{0xF0, 0x07}, "NMEA-GST", all, output, true},
    {{0xF0, 0x08}, "NMEA-ZDA", all, output, true},
    {{0xF0, 0x09}, "NMEA-GBS", all, output, true},
    {{0xF0, 0x0A}, "NMEA-DTM", all, output, true},
    {{0xF0, 0x0D}, "NMEA-GNS", all, output, true},
    {{0xF0, 0x0F}, "NMEA-VLW", all, output, true},
}};
// clang-format on

/// CFG-MSGOUT keys of one message, by Port (I2C, UART1, UART2, USB, SPI).
struct MsgOutKeys {
  MessageId id;
  std::array<std::uint32_t, 5> keys{};
};

/// "CFG-MSGOUT-UBX_NAV_PVT" / "CFG-MSGOUT-NMEA_ID_GGA": the stem of a message's MSGOUT keys.
std::string msgout_stem(std::string_view name) {
  std::string stem = name.starts_with("NMEA-") ? "NMEA_ID_" + std::string(name.substr(5)) : "UBX_" + std::string(name);
  std::replace(stem.begin(), stem.end(), '-', '_');
  return "CFG-MSGOUT-" + stem;
}

const std::vector<MsgOutKeys>& msgout_keys() {
  static const std::vector<MsgOutKeys> all = [] {
    std::vector<MsgOutKeys> v;
    constexpr std::array<std::string_view, 5> ports = {"_I2C", "_UART1", "_UART2", "_USB", "_SPI"};
    for (const MessageRow& row : kTable) {
      if (!row.msgout) continue;
      MsgOutKeys k{row.id, {}};
      for (std::size_t p = 0; p < ports.size(); ++p) k.keys[p] = key_id(msgout_stem(row.name) + std::string(ports[p]));
      v.push_back(k);
    }
    return v;
  }();
  return all;
}

}  // namespace

ModelSet model_bit(ReceiverModel model) {
  switch (model) {
    case ReceiverModel::ublox_m9n: return m9n;
    case ReceiverModel::ublox_f9p: return f9p;
    case ReceiverModel::ublox_m10: return m10;
    default: return m8;
  }
}

std::span<const MessageRow> message_table() { return kTable; }

const MessageRow* find_message(MessageId id) {
  for (const MessageRow& row : kTable) {
    if (row.id == id) return &row;
  }
  return nullptr;
}

const MessageRow* find_message(std::string_view name) {
  for (const MessageRow& row : kTable) {
    if (row.name == name) return &row;
  }
  return nullptr;
}

bool model_has_message(ReceiverModel model, MessageId id) {
  const MessageRow* row = find_message(id);
  return row == nullptr || (row->models & model_bit(model)) != 0;
}

bool solution_encodes(MessageId id) {
  const MessageRow* row = find_message(id);
  return row != nullptr && row->encode != nullptr;
}

std::optional<std::string> solution_payload(MessageId id, const nmea::Fix& fix, const NavExtras& extras) {
  const MessageRow* row = find_message(id);
  if (row == nullptr || row->encode == nullptr) return std::nullopt;
  return row->encode(fix, extras);
}

std::optional<std::uint32_t> msgout_key(MessageId id, Port port) {
  if (static_cast<std::size_t>(port) >= 5) return std::nullopt;
  for (const MsgOutKeys& m : msgout_keys()) {
    if (m.id == id) return m.keys[static_cast<std::size_t>(port)];
  }
  return std::nullopt;
}

std::optional<std::pair<MessageId, Port>> msgout_of(std::uint32_t key) {
  for (const MsgOutKeys& m : msgout_keys()) {
    for (std::size_t p = 0; p < m.keys.size(); ++p) {
      if (m.keys[p] == key) return std::pair{m.id, static_cast<Port>(p)};
    }
  }
  return std::nullopt;
}

std::optional<MessageId> msgout_message(std::uint32_t key) {
  if (const auto m = msgout_of(key)) return m->first;
  return std::nullopt;
}

std::string message_name(MessageId id) {
  if (const MessageRow* row = find_message(id)) return std::string(row->name);
  return fmt::format("0x{:02X}-0x{:02X}", id.msg_class, id.msg_id);
}

}  // namespace gpsemu::ubx
