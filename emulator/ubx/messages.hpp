// The UBX message table: each message gpsemu knows is one row (class/id, name, the receiver
// models whose interface description has it, what it is to the receiver, whether it has
// CFG-MSGOUT keys, its encoder and payload layout). Output order, the CFG-MSGOUT keys of each
// port (found by name in the key catalogue: CFG-MSGOUT-UBX_NAV_PVT_I2C, _UART1, _UART2, _USB,
// _SPI), which model NAKs what, poll answers and docs/ublox.md's message list all read it.
// Adding an output message is one row here, its layout (layouts.hpp) and its encoder. Pure.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "emulator/ubx/fields.hpp"
#include "emulator/ubx/frame.hpp"
#include "emulator/ubx/model.hpp"
#include "emulator/ubx/nav.hpp"
#include "emulator/ubx/pubx.hpp"

namespace gpsemu::ubx {

/// Sets of receiver models, one bit per model family (generic answers as an M8).
using ModelSet = std::uint8_t;
namespace models {
inline constexpr ModelSet m8 = 1u << 0;   ///< generic, ublox-m8n (protocol 18)
inline constexpr ModelSet m9n = 1u << 1;  ///< ublox-m9n (SPG 4.04)
inline constexpr ModelSet f9p = 1u << 2;  ///< ublox-f9p (HPG 1.32)
inline constexpr ModelSet m10 = 1u << 3;  ///< ublox-m10 (SPG 5.10)
inline constexpr ModelSet all = m8 | m9n | f9p | m10;
inline constexpr ModelSet generation9 = m9n | f9p | m10;  ///< protocol 27+: the key/value interface
}  // namespace models
/// The bit of `model` in a ModelSet.
[[nodiscard]] ModelSet model_bit(ReceiverModel model);

/// What a message is to the receiver.
enum class MessageRole : std::uint8_t {
  solution,  ///< written with each navigation solution at its rate (and once when polled)
  report,    ///< written when something happens (RXM-RTCM for each RTCM3 message taken, ACK)
  poll,      ///< answered to a poll only (MON-VER)
  input,     ///< written by the client (CFG-*): configuration
  output,    ///< a rate can be set (CFG-MSGOUT) but gpsemu writes nothing (RXM-RAWX, NAV-SBAS...)
};

/// The payload of a solution message.
using Encoder = std::string (*)(const nmea::Fix& fix, const NavExtras& extras);

struct MessageRow {
  MessageId id;
  std::string_view name;  ///< "NAV-PVT"; NMEA standard messages "NMEA-GGA"
  ModelSet models = models::all;
  MessageRole role = MessageRole::solution;
  bool msgout = false;      ///< has CFG-MSGOUT-<UBX|NMEA_ID>_<name>_<port> keys (and a CFG-MSG rate)
  Encoder encode = nullptr; ///< solution messages
  Layout fields = {};       ///< the payload (the fixed part of one with repeated blocks)
  Layout block = {};        ///< one repeated block (NAV-SAT's satellites...), empty when none
};

/// Every row, by class then id (the order a u-blox writes a solution's messages in).
[[nodiscard]] std::span<const MessageRow> message_table();
/// The row of `id`, nullptr for a message the table lacks.
[[nodiscard]] const MessageRow* find_message(MessageId id);
/// The row named `name` ("NAV-PVT"), nullptr for another name.
[[nodiscard]] const MessageRow* find_message(std::string_view name);

/// Whether `model` has message `id` in its interface description (its row's models); a message
/// the table lacks: true (not modelled per model).
[[nodiscard]] bool model_has_message(ReceiverModel model, MessageId id);
/// Whether `id` is a message written with a solution (a row with an encoder).
[[nodiscard]] bool solution_encodes(MessageId id);
/// The payload of solution message `id`, nullopt for a message not encoded.
[[nodiscard]] std::optional<std::string> solution_payload(MessageId id, const nmea::Fix& fix, const NavExtras& extras);

/// The CFG-MSGOUT key of message `id` on `port`, nullopt for a message without one.
[[nodiscard]] std::optional<std::uint32_t> msgout_key(MessageId id, Port port);
/// The message and port of a CFG-MSGOUT key, nullopt for another key.
[[nodiscard]] std::optional<std::pair<MessageId, Port>> msgout_of(std::uint32_t key);
/// The message a CFG-MSGOUT key sets the rate of (any port), nullopt for another key.
[[nodiscard]] std::optional<MessageId> msgout_message(std::uint32_t key);
/// The name of `id`: its row's ("NAV-PVT"), else "0x01-0x99".
[[nodiscard]] std::string message_name(MessageId id);

}  // namespace gpsemu::ubx
