// The configuration a u-blox keeps in RAM, as values: measurement rate, each port's baud and
// protocols, each message's output rate per port (UBX and NMEA, class 0xF0), and the navigation
// (CFG-NAV5), GNSS and SBAS blocks a client may poll and write back. The configuration machine
// (machine.hpp) changes it; the UBX encoder reads it. Pure values.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/ubx/frame.hpp"
#include "emulator/ubx/model.hpp"
#include "emulator/ubx/pubx.hpp"
#include "nmea/sentence_set.hpp"

namespace gpsemu::ubx {

/// Protocol mask bits of CFG-PRT and $PUBX,41.
inline constexpr std::uint16_t proto_ubx = 0x0001;
inline constexpr std::uint16_t proto_nmea = 0x0002;
inline constexpr std::uint16_t proto_rtcm3 = 0x0020;

struct PortSettings {
  std::uint32_t baud = 0;              ///< bits per second (0 for USB, I2C, SPI)
  std::uint32_t mode = 0x000008D0;     ///< CFG-PRT mode: 8N1
  std::uint16_t in_proto_mask = proto_ubx | proto_nmea | proto_rtcm3;
  std::uint16_t out_proto_mask = proto_ubx | proto_nmea;
};

/// Output rate of one message on each port, in navigation epochs (0 off, 1 every epoch...).
using PortRates = std::array<std::uint8_t, port_count>;

/// What the receiver starts with (the emulator's configuration).
struct StartSettings {
  ReceiverModel model = ReceiverModel::generic;
  Port port = Port::uart1;  ///< the port the client is connected to
  std::chrono::milliseconds measurement_period{1000};
  nmea::SentenceSet sentences = nmea::SentenceSet::ublox_default();  ///< NMEA on at start
  std::vector<MessageId> ubx_messages;  ///< UBX messages on at start, every epoch
  std::uint32_t baud = 0;               ///< the client port's baud; 0: the model's default
};

struct Settings {
  std::uint16_t meas_period_ms = 1000;  ///< CFG-RATE measRate (milliseconds)
  std::uint16_t nav_rate_cycles = 1;    ///< CFG-RATE navRate (measurements per solution)
  std::uint16_t time_ref = 1;           ///< CFG-RATE timeRef: 0 UTC, 1 GPS
  std::array<PortSettings, port_count> ports{};
  std::map<MessageId, PortRates> rates;  ///< a message not listed is off on every port
  std::string nav5;  ///< CFG-NAV5 payload (36 bytes); dynModel at byte 2, fixMode at byte 3
  std::string gnss;  ///< CFG-GNSS payload (4 + 8 per block)
  std::string sbas;  ///< CFG-SBAS payload (8 bytes)
  std::map<std::uint32_t, std::uint64_t> other_keys;  ///< CFG-VALSET keys without a modelled effect

  [[nodiscard]] std::uint8_t rate(MessageId id, Port port) const;
  void set_rate(MessageId id, Port port, std::uint8_t rate);
  /// The time between navigation solutions (measRate x navRate).
  [[nodiscard]] std::chrono::milliseconds output_period() const {
    return std::chrono::milliseconds{static_cast<int>(meas_period_ms) * nav_rate_cycles};
  }
  [[nodiscard]] std::uint8_t dyn_model() const { return nav5.size() > 2 ? static_cast<std::uint8_t>(nav5[2]) : 0; }
};

/// The settings a receiver of `start` has after power-up.
[[nodiscard]] Settings start_settings(const StartSettings& start);

/// Class 0xF0 id of an NMEA sentence type (GGA 0x00, GLL 0x01, GSA 0x02, GSV 0x03, RMC 0x04,
/// VTG 0x05, GST 0x07, ZDA 0x08); nullopt for HDT and THS, which a u-blox F9P does not write.
[[nodiscard]] std::optional<MessageId> nmea_message(nmea::SentenceType type);
/// The sentence type of an NMEA message id, nullopt for another message.
[[nodiscard]] std::optional<nmea::SentenceType> sentence_of(MessageId id);
/// The NMEA message named `name` ("GGA", also GRS GBS DTM GNS VLW which gpsemu never writes).
[[nodiscard]] std::optional<MessageId> nmea_message_from_name(std::string_view name);

}  // namespace gpsemu::ubx
