// u-blox's proprietary NMEA commands a client may write instead of UBX: $PUBX,40 (one NMEA
// message's output rate on each port) and $PUBX,41 (a port's protocols and baud rate; ArduPilot
// sends one while it looks for the receiver). Pure: a checked nmea::Sentence in, values out.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "nmea/parse.hpp"

namespace gpsemu::ubx {

/// Ports of a u-blox receiver, in CFG-MSG's rate order (UBX port ids).
enum class Port : std::uint8_t { i2c = 0, uart1 = 1, uart2 = 2, usb = 3, spi = 4, reserved = 5 };
inline constexpr std::size_t port_count = 6;

/// $PUBX,40,msgId,rddc,rus1,rus2,rusb,rspi,reserved: the output rate of one NMEA message on each
/// port, in navigation epochs (0 off).
struct Pubx40 {
  std::string message;  ///< "GGA", "RMC", ...
  std::array<std::uint8_t, port_count> rates{};  ///< per Port (reserved: 0)
};

/// $PUBX,41,portId,inProto,outProto,baudrate,autobauding: a port's configuration.
struct Pubx41 {
  Port port = Port::uart1;
  std::uint16_t in_proto_mask = 0;   ///< bit 0 UBX, bit 1 NMEA, bit 5 RTCM3
  std::uint16_t out_proto_mask = 0;
  std::uint32_t baud = 0;            ///< bits per second
};

/// The command in `sentence`, or nullopt when it is no well-formed $PUBX,40.
[[nodiscard]] std::optional<Pubx40> parse_pubx40(const nmea::Sentence& sentence);
/// The command in `sentence`, or nullopt when it is no well-formed $PUBX,41.
[[nodiscard]] std::optional<Pubx41> parse_pubx41(const nmea::Sentence& sentence);

}  // namespace gpsemu::ubx
