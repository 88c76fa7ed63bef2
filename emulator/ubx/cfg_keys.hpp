// The generation-9 key/value configuration (CFG-VALSET, CFG-VALGET, CFG-VALDEL) over Settings.
// A key's id carries its value's size (bits 28-30: 1 bit, 1, 2, 4 or 8 bytes). Modelled keys
// map onto Settings (CFG-RATE-*, CFG-UARTn-BAUDRATE, CFG-<port>INPROT/OUTPROT-*, CFG-NAVSPG-*
// of CFG-NAV5, CFG-MSGOUT-* of the messages PX4's and ArduPilot's drivers configure, and of
// NAV-SVINFO and NAV-SBAS, which a u-blox 9 NAKs as messages it lacks); any other
// well-formed key is kept as written so that a VALGET reads it back. Pure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>

#include "emulator/ubx/messages.hpp"
#include "emulator/ubx/settings.hpp"

namespace gpsemu::ubx {

namespace key {
inline constexpr std::uint32_t rate_meas = 0x30210001;
inline constexpr std::uint32_t rate_nav = 0x30210002;
inline constexpr std::uint32_t rate_timeref = 0x20210003;
inline constexpr std::uint32_t uart1_baudrate = 0x40520001;
inline constexpr std::uint32_t uart2_baudrate = 0x40530001;
inline constexpr std::uint32_t uart1inprot_ubx = 0x10730001;
inline constexpr std::uint32_t uart1outprot_ubx = 0x10740001;
inline constexpr std::uint32_t uart1outprot_nmea = 0x10740002;
inline constexpr std::uint32_t navspg_fixmode = 0x20110011;
inline constexpr std::uint32_t navspg_dynmodel = 0x20110021;
inline constexpr std::uint32_t msgout_nav_pvt_i2c = 0x20910006;  ///< + Port: UART1 is 0x20910007
inline constexpr std::uint32_t msgout_nmea_gga_i2c = 0x209100BA;
}  // namespace key

/// Bytes `key`'s value takes in a CFG-VALSET/VALGET (a 1-bit value takes one byte); 0 when
/// the size bits are invalid.
[[nodiscard]] std::size_t key_value_bytes(std::uint32_t key);
/// The current value of `key`, nullopt for a key that is neither modelled nor ever written.
[[nodiscard]] std::optional<std::uint64_t> get_key(const Settings& s, std::uint32_t key);
/// Whether set_key() would take `value` for `key`: a key the receiver knows (cfg_key_catalogue.hpp),
/// a modelled key's value in its range.
[[nodiscard]] bool key_accepts(std::uint32_t key, std::uint64_t value);
/// Writes `key`; false (nothing changed) when key_accepts() is false.
[[nodiscard]] bool set_key(Settings& s, std::uint32_t key, std::uint64_t value);
/// Calls `f` with every key that maps onto Settings (rates, ports, CFG-NAVSPG, CFG-MSGOUT).
void for_each_modelled_key(const std::function<void(std::uint32_t)>& f);

}  // namespace gpsemu::ubx
