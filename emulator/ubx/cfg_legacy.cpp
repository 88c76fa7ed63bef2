// Classic CFG messages and PUBX commands over Settings (see cfg_legacy.hpp).
#include "emulator/ubx/cfg_legacy.hpp"

#include <algorithm>
#include <array>
#include <utility>

#include "emulator/ubx/bytes.hpp"

namespace gpsemu::ubx {
namespace {

constexpr std::size_t kPrtBytes = 20;
constexpr std::size_t kNav5Bytes = 36;
constexpr std::size_t kGnssBlockBytes = 8;

/// CFG-NAV5 mask bit -> byte ranges [first, last) of the payload it selects.
struct Nav5Group {
  std::uint16_t bit;
  std::array<std::pair<std::size_t, std::size_t>, 2> ranges;
};
constexpr std::array<Nav5Group, 10> kNav5Groups = {{
    {0x0001, {{{2, 3}, {0, 0}}}},     // dyn: dynModel
    {0x0002, {{{12, 13}, {0, 0}}}},   // minEl
    {0x0004, {{{3, 12}, {0, 0}}}},    // posFixMode: fixMode, fixedAlt, fixedAltVar
    {0x0008, {{{13, 14}, {0, 0}}}},   // drLim
    {0x0010, {{{14, 16}, {18, 20}}}}, // posMask: pDop, pAcc
    {0x0020, {{{16, 18}, {20, 22}}}}, // timeMask: tDop, tAcc
    {0x0040, {{{22, 23}, {28, 30}}}}, // staticHoldMask
    {0x0080, {{{23, 24}, {0, 0}}}},   // dgpsMask: dgnssTimeout
    {0x0100, {{{24, 26}, {0, 0}}}},   // cnoThreshold
    {0x0400, {{{30, 31}, {0, 0}}}},   // utc: utcStandard
}};

}  // namespace

bool is_supported_baud(std::uint64_t baud) {
  constexpr std::array<std::uint32_t, 9> bauds = {4800, 9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600};
  return std::find(bauds.begin(), bauds.end(), baud) != bauds.end();
}

bool is_dyn_model(std::uint64_t model) { return model == 0 || (model >= 2 && model <= 12); }

std::string cfg_prt_payload(const Settings& s, Port port) {
  const PortSettings& p = s.ports[static_cast<std::size_t>(port)];
  std::string out;
  put_u1(out, static_cast<std::uint32_t>(port));
  put_u1(out, 0);  // reserved
  put_u2(out, 0);  // txReady
  put_u4(out, port == Port::uart1 || port == Port::uart2 ? p.mode : 0);
  put_u4(out, p.baud);
  put_u2(out, p.in_proto_mask);
  put_u2(out, p.out_proto_mask);
  put_u2(out, 0);  // flags
  put_zeros(out, 2);
  return out;
}

bool apply_cfg_prt(Settings& s, std::string_view payload) {
  if (payload.empty() || payload.size() % kPrtBytes != 0) return false;
  Settings next = s;
  for (std::size_t at = 0; at < payload.size(); at += kPrtBytes) {
    const std::uint8_t id = get_u1(payload, at);
    if (id > static_cast<std::uint8_t>(Port::spi)) return false;
    PortSettings& p = next.ports[id];
    const bool uart = id == static_cast<std::uint8_t>(Port::uart1) || id == static_cast<std::uint8_t>(Port::uart2);
    if (uart) {
      const std::uint32_t baud = get_u4(payload, at + 8);
      if (!is_supported_baud(baud)) return false;
      p.baud = baud;
      p.mode = get_u4(payload, at + 4);
    }
    p.in_proto_mask = get_u2(payload, at + 12);
    p.out_proto_mask = get_u2(payload, at + 14);
  }
  s = std::move(next);
  return true;
}

std::string cfg_msg_payload(const Settings& s, MessageId id) {
  std::string out;
  put_u1(out, id.msg_class);
  put_u1(out, id.msg_id);
  for (std::size_t port = 0; port < port_count; ++port) put_u1(out, s.rate(id, static_cast<Port>(port)));
  return out;
}

bool apply_cfg_msg(Settings& s, std::string_view payload, Port client_port) {
  const MessageId id{get_u1(payload, 0), get_u1(payload, 1)};
  if (payload.size() == 3) {
    s.set_rate(id, client_port, get_u1(payload, 2));
    return true;
  }
  if (payload.size() != 2 + port_count) return false;
  for (std::size_t port = 0; port < port_count; ++port) s.set_rate(id, static_cast<Port>(port), get_u1(payload, 2 + port));
  return true;
}

std::string cfg_rate_payload(const Settings& s) {
  std::string out;
  put_u2(out, s.meas_period_ms);
  put_u2(out, s.nav_rate_cycles);
  put_u2(out, s.time_ref);
  return out;
}

bool apply_cfg_rate(Settings& s, std::string_view payload) {
  if (payload.size() != 6) return false;
  const std::uint16_t meas_ms = get_u2(payload, 0);
  const std::uint16_t nav = get_u2(payload, 2);
  const std::uint16_t time_ref = get_u2(payload, 4);
  if (meas_ms < min_meas_period_ms || nav < 1 || nav > 127 || time_ref > 5) return false;
  s.meas_period_ms = meas_ms;
  s.nav_rate_cycles = nav;
  s.time_ref = time_ref;
  return true;
}

bool apply_cfg_nav5(Settings& s, std::string_view payload) {
  if (payload.size() != kNav5Bytes) return false;
  const std::uint16_t mask = get_u2(payload, 0);
  if ((mask & 0x0001) != 0 && !is_dyn_model(get_u1(payload, 2))) return false;
  if ((mask & 0x0004) != 0 && (get_u1(payload, 3) < 1 || get_u1(payload, 3) > 3)) return false;
  for (const Nav5Group& group : kNav5Groups) {
    if ((mask & group.bit) == 0) continue;
    for (const auto& [first, last] : group.ranges) {
      for (std::size_t i = first; i < last; ++i) s.nav5[i] = payload[i];
    }
  }
  return true;
}

bool apply_cfg_gnss(Settings& s, std::string_view payload) {
  if (payload.size() < 4) return false;
  const std::size_t blocks = get_u1(payload, 3);
  if (payload.size() != 4 + blocks * kGnssBlockBytes) return false;
  const std::size_t stored = get_u1(s.gnss, 3);
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::string_view block = payload.substr(4 + b * kGnssBlockBytes, kGnssBlockBytes);
    for (std::size_t k = 0; k < stored; ++k) {
      const std::size_t at = 4 + k * kGnssBlockBytes;
      if (static_cast<char>(get_u1(s.gnss, at)) == block[0]) s.gnss.replace(at, kGnssBlockBytes, block);
    }
  }
  if (get_u1(payload, 2) != 0xFF) s.gnss[2] = payload[2];  // numTrkChUse (0xFF: all there are)
  return true;
}

bool apply_cfg_sbas(Settings& s, std::string_view payload) {
  if (payload.size() != 8) return false;
  s.sbas = std::string(payload);
  return true;
}

bool apply_pubx40(Settings& s, const Pubx40& cmd) {
  const std::optional<MessageId> id = nmea_message_from_name(cmd.message);
  if (!id) return false;
  for (std::size_t port = 0; port < port_count; ++port) s.set_rate(*id, static_cast<Port>(port), cmd.rates[port]);
  return true;
}

bool apply_pubx41(Settings& s, const Pubx41& cmd) {
  const bool uart = cmd.port == Port::uart1 || cmd.port == Port::uart2;
  if (uart && !is_supported_baud(cmd.baud)) return false;
  PortSettings& p = s.ports[static_cast<std::size_t>(cmd.port)];
  if (uart) p.baud = cmd.baud;
  p.in_proto_mask = cmd.in_proto_mask;
  p.out_proto_mask = cmd.out_proto_mask;
  return true;
}

}  // namespace gpsemu::ubx
