// The classic configuration messages (CFG-PRT, CFG-MSG, CFG-RATE, CFG-NAV5, CFG-GNSS, CFG-SBAS)
// and the NMEA commands $PUBX,40/41, as pure functions over Settings: the payload a poll is
// answered with, and applying a written payload (false: the receiver NAKs it and nothing changes).
#pragma once

#include <string>
#include <string_view>

#include "emulator/ubx/pubx.hpp"
#include "emulator/ubx/settings.hpp"

namespace gpsemu::ubx {

/// Shortest measurement period a u-blox accepts (milliseconds).
inline constexpr int min_meas_period_ms = 25;
/// Whether `baud` is one a u-blox UART can be set to.
[[nodiscard]] bool is_supported_baud(std::uint64_t baud);
/// Whether `model` is a CFG-NAV5 / CFG-NAVSPG-DYNMODEL dynamic platform model.
[[nodiscard]] bool is_dyn_model(std::uint64_t model);

/// CFG-PRT (20 bytes) of `port`.
[[nodiscard]] std::string cfg_prt_payload(const Settings& s, Port port);
/// One or more 20-byte port blocks (PX4 writes UART1 and USB in one message).
[[nodiscard]] bool apply_cfg_prt(Settings& s, std::string_view payload);

/// CFG-MSG (8 bytes: class, id, a rate per port) of `id`.
[[nodiscard]] std::string cfg_msg_payload(const Settings& s, MessageId id);
/// 3 bytes (the rate on `client_port`) or 8 bytes (a rate per port).
[[nodiscard]] bool apply_cfg_msg(Settings& s, std::string_view payload, Port client_port);

/// CFG-RATE (6 bytes: measRate ms, navRate cycles, timeRef).
[[nodiscard]] std::string cfg_rate_payload(const Settings& s);
[[nodiscard]] bool apply_cfg_rate(Settings& s, std::string_view payload);

/// 36 bytes; only the parameter groups its mask selects change.
[[nodiscard]] bool apply_cfg_nav5(Settings& s, std::string_view payload);
/// 4 + 8 per block; each block replaces the stored block of its gnssId.
[[nodiscard]] bool apply_cfg_gnss(Settings& s, std::string_view payload);
/// 8 bytes.
[[nodiscard]] bool apply_cfg_sbas(Settings& s, std::string_view payload);

/// $PUBX,40: a known NMEA message's rate on each port.
[[nodiscard]] bool apply_pubx40(Settings& s, const Pubx40& cmd);
/// $PUBX,41: a port's protocols and baud.
[[nodiscard]] bool apply_pubx41(Settings& s, const Pubx41& cmd);

}  // namespace gpsemu::ubx
